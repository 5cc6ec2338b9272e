#include "raytrace/trace_options.h"

#include "core/error.h"

namespace rfidray {

const char* to_string(CandidateMode mode) {
  return mode == CandidateMode::kExhaustive ? "exhaustive" : "fast";
}

CandidateMode parse_candidate_mode(const std::string& name, const std::string& field) {
  if (name == "exhaustive") return CandidateMode::kExhaustive;
  if (name == "fast") return CandidateMode::kFast;
  throw field_error(field, "unknown candidate mode '" + clip(name) + "' (exhaustive, fast)");
}

}  // namespace rfidray
