#pragma once
// Synthetic phase histories from geometry, for tests, sweeps and the paper reproduction:
//   φ_k = (φ0(channel) + 4π|T − P_k|/λ + n_k) mod 2π,  n_k ~ N(0, σ²)  (paper eq. 4 with the ideal channel).
#include <cstdint>
#include <vector>

#include "localization/observations.h"

namespace rfidray::loc {

struct PathSample {
  double time_s = 0.0;
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
};

// Constant-speed traversal of a polyline sampled at rate_hz; orientation = heading yaw + antenna_yaw_rad
// (boresight +X, so antenna_yaw = −π/2 looks to the right of the direction of travel).
std::vector<PathSample> sample_polyline(const std::vector<Vec3>& waypoints, double speed_m_s, double rate_hz,
                                        double antenna_yaw_rad = 0.0);

struct SyntheticSpec {
  std::vector<double> frequencies_hz{865.7e6};  // several: hopping in this order every hop_dwell_s
  std::vector<double> phase_offsets_rad{0.0};
  double hop_dwell_s = 0.4;
  double phase_noise_rad = 0.0;
  double read_range_m = 1e9;     // reads only within this distance
  int phase_bits = 0;            // quantization, 0: none
  bool signed_phase = false;     // report in (−π, π] instead of [0, 2π)
  uint64_t seed = 1;
  uint64_t stream = 0;           // e.g. tag index: independent noise per tag
  std::string antenna = "a0";
};

TagReads synthesize(const std::string& tag_name, const Vec3& tag_m, const std::vector<PathSample>& path,
                    const SyntheticSpec& spec);

}  // namespace rfidray::loc
