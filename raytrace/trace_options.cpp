#include "raytrace/trace_options.h"

#include "core/error.h"

namespace rfidray {

const char* to_string(ChannelLevel level) {
  switch (level) {
    case ChannelLevel::kLos: return "los";
    case ChannelLevel::kLosBlocked: return "los+blocked";
    case ChannelLevel::kSingleBounce: return "single-bounce";
  }
  return "?";
}

const char* to_string(CandidateMode mode) {
  return mode == CandidateMode::kExhaustive ? "exhaustive" : "fast";
}

ChannelLevel parse_channel_level(const std::string& name, const std::string& field) {
  if (name == "los") return ChannelLevel::kLos;
  if (name == "los+blocked") return ChannelLevel::kLosBlocked;
  if (name == "single-bounce") return ChannelLevel::kSingleBounce;
  throw field_error(field, "unknown channel level '" + name + "' (los, los+blocked, single-bounce)");
}

CandidateMode parse_candidate_mode(const std::string& name, const std::string& field) {
  if (name == "exhaustive") return CandidateMode::kExhaustive;
  if (name == "fast") return CandidateMode::kFast;
  throw field_error(field, "unknown candidate mode '" + name + "' (exhaustive, fast)");
}

}  // namespace rfidray
