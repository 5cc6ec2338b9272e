#pragma once
// What a channel models, as one type from the scenario file to the ray tracer. The name exists only at the
// file / command-line boundary (parse_channel_level, to_string). Each modelled level includes the previous one,
// so levels order by what they model, and by cost. Values only; thread-safe.
#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace rfidray {

enum class ChannelLevel {
  kIdeal,         // "ideal": one line-of-sight path, no scene (the paper's free-space model, eq. 1)
  kLos,           // "los": the direct path if unoccluded, else nothing (h = 0)
  kLosBlocked,    // "los+blocked": the direct path, through obstacles (transmission loss per crossed surface)
  kSingleBounce,  // "single-bounce": + every single specular reflection (image method), both legs unoccluded
  kDoubleBounce,  // "double-bounce": + every specular path with two reflections (image of the image), all legs
  kFullSelective, // "full-selective": full without its weakest diffractions, all it leaves out summing to at most
                  //   a fraction ε of |h| (TraceOptions::diffraction_skipped_fraction; raytrace/diffraction.cpp)
  kFull,          // "full": + first-order edge diffraction (UTD, core/utd.h) at wedges and free sheet edges, and
                  //   the edge's near field at an end close to it (core/edge_near_field.h)
  kAuto,          // "auto": not a model — pick the cheapest level the scenario needs (raytrace/fidelity.h)
};

// The modelled levels, cheapest first (kAuto is not among them).
inline constexpr std::array<ChannelLevel, 7> kModelledLevels{
    ChannelLevel::kIdeal,        ChannelLevel::kLos,          ChannelLevel::kLosBlocked,
    ChannelLevel::kSingleBounce, ChannelLevel::kDoubleBounce, ChannelLevel::kFullSelective,
    ChannelLevel::kFull};

// True when a modelled `level` includes what `feature` adds (levels are cumulative; kAuto includes nothing).
constexpr bool includes(ChannelLevel level, ChannelLevel feature) {
  return level != ChannelLevel::kAuto && static_cast<int>(level) >= static_cast<int>(feature);
}

// True for the levels the ray tracer computes (a scene is needed).
constexpr bool is_traced(ChannelLevel level) {
  return level != ChannelLevel::kIdeal && level != ChannelLevel::kAuto;
}

// "ideal", "los", "los+blocked", "single-bounce", "double-bounce", "full-selective", "full", "auto".
const char* to_string(ChannelLevel level);
// Every name, in the order above, comma-separated (for --help and messages).
std::string channel_level_names();
// nullopt for an unknown name.
std::optional<ChannelLevel> parse_channel_level(std::string_view name);
// Throws InputError "field 'FIELD': unknown channel 'NAME' (known: ...)".
ChannelLevel parse_channel_level(const std::string& name, const std::string& field);

}  // namespace rfidray
