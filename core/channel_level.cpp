#include "core/channel_level.h"

#include "core/error.h"

namespace rfidray {
namespace {

constexpr std::array<ChannelLevel, 8> kAll{ChannelLevel::kIdeal,        ChannelLevel::kLos,
                                           ChannelLevel::kLosBlocked,   ChannelLevel::kSingleBounce,
                                           ChannelLevel::kDoubleBounce, ChannelLevel::kFullSelective,
                                           ChannelLevel::kFull,         ChannelLevel::kAuto};

}  // namespace

const char* to_string(ChannelLevel level) {
  switch (level) {
    case ChannelLevel::kIdeal: return "ideal";
    case ChannelLevel::kLos: return "los";
    case ChannelLevel::kLosBlocked: return "los+blocked";
    case ChannelLevel::kSingleBounce: return "single-bounce";
    case ChannelLevel::kDoubleBounce: return "double-bounce";
    case ChannelLevel::kFullSelective: return "full-selective";
    case ChannelLevel::kFull: return "full";
    case ChannelLevel::kAuto: return "auto";
  }
  return "?";
}

std::string channel_level_names() {
  std::string out;
  for (ChannelLevel l : kAll) out += (out.empty() ? "" : ", ") + std::string(to_string(l));
  return out;
}

std::optional<ChannelLevel> parse_channel_level(std::string_view name) {
  for (ChannelLevel l : kAll)
    if (name == to_string(l)) return l;
  return std::nullopt;
}

ChannelLevel parse_channel_level(const std::string& name, const std::string& field) {
  if (const auto l = parse_channel_level(std::string_view(name))) return *l;
  throw field_error(field, "unknown channel '" + clip(name) + "' (known: " + channel_level_names() + ")");
}

}  // namespace rfidray
