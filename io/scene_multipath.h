#pragma once
// The known-scene multipath allowance of `rfidray localize --scenario` (localization/multipath_allowance.h),
// computed with the scenario's own channel.
//
// For a tag's reads, allowance_for() returns x ↦ RMS (rad) of ε_k = 2·arg(h_k(x) / h0_k(x)) about its mean,
// over up to kSamples reads spread evenly in time: h_k the one-way channel of the scenario's level (every
// path its scene has) from the read's antenna pose to a tag at x, h0_k = e^{−jkD}/D the free-space direct path
// (antenna and tag gains are real and drop out of the phase). Antenna pattern and polarization are those of
// the scenario antenna the reads name (the CSV's `antenna` column; the only antenna when there is one), the
// tag's those of the scenario tag of the same name, its orientation that of its (first) pose; a tag the
// scenario does not have is taken as the default tag facing +x.
//
// Thread safety: the returned functions only read the channel (thread-safe) and may be called concurrently.
// Throws InputError (naming the scenario) when the scenario cannot be loaded or its channel built, and from
// allowance_for when reads name an antenna the scenario does not have.
#include <complex>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "core/channel.h"
#include "core/scenario.h"
#include "localization/observations.h"

namespace rfidray::io {

class SceneMultipath {
 public:
  static constexpr int kSamples = 64;

  explicit SceneMultipath(const Scenario& scenario);
  std::function<double(const Vec3& tag_m)> allowance_for(const loc::TagReads& tag) const;

 private:
  Scenario scenario_;
  std::shared_ptr<const Channel> channel_;
};

// `localize --scenario FILE [--channel LEVEL]`: the scenario file, its level replaced by `channel` when given
// (`channel_field` names that option in the error for an unknown level).
SceneMultipath load_scene_multipath(const std::string& scenario_file, const std::optional<std::string>& channel,
                                    const std::string& channel_field);

}  // namespace rfidray::io
