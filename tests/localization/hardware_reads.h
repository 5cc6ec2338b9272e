#pragma once
// Test generator of reads with hardware-like effects (no library code depends on it): stop-and-go sampling
// of an antenna path, hopping carriers with per-carrier chain offsets, a phase-centre offset and an
// angle-dependent phase pattern (the antenna_calibration.h model), a per-tag offset, Gaussian phase noise,
// uniformly random outlier reads, and optionally a second propagation path off a wall behind the tag:
//   h = e^{−jkD} + Γ e^{−jkD'},  φ = −arg(h²)  (round trip; D' = distance to the tag's image in the wall).
#include <cmath>
#include <complex>
#include <optional>
#include <random>
#include <vector>

#include "core/units.h"
#include "localization/antenna_calibration.h"
#include "localization/observations.h"

namespace rfidray::loc::testing {

struct Stop {
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
};

// Straight stage along +x from `start`, `count` stops `step_m` apart, boresight +y (yaw +90°).
inline std::vector<Stop> straight_stage(const Vec3& start, int count, double step_m) {
  std::vector<Stop> s;
  const Quat yaw(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()));
  for (int i = 0; i < count; ++i) s.push_back({start + Vec3(step_m * i, 0, 0), yaw});
  return s;
}

inline std::vector<double> adarf_carriers_hz() {
  std::vector<double> f;
  for (int i = 0; i < 8; ++i) f.push_back(920.625e6 + 0.5e6 * i);
  return f;
}

struct Hardware {
  AntennaCalibration truth;        // phase centre, carrier offsets (per frequencies_hz) and pattern
  double tag_offset_rad = 0.0;     // ν of this tag
  double noise_rad = 0.1;
  double outlier_fraction = 0.0;
  int reads_per_stop = 5;          // per carrier
  double wall_gamma = 0.0;         // 0: no wall
  double wall_y_m = 0.0;           // wall plane y = wall_y_m (behind the tag, seen from the antenna)
  bool fold_pi = false;            // add π to a random half of the reads (a reader's π ambiguity)
};

inline TagReads hardware_reads(const std::string& name, const Vec3& tag, const std::vector<Stop>& stops,
                               const Hardware& hw, uint64_t seed, const std::string& antenna = "a0") {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  TagReads out;
  out.tag = name;
  const auto& freqs = hw.truth.frequencies_hz;
  for (double f : freqs) out.groups.push_back(ReadGroup{antenna, f, {}});
  double t = 0.0;
  for (const Stop& s : stops) {
    const Vec3 centre = hw.truth.phase_centre(s.position, s.orientation);
    double az, el;
    direction_in_frame(centre, s.orientation, tag, az, el);
    const double pattern = hw.truth.pattern_phase_rad(az, el);
    for (size_t c = 0; c < freqs.size(); ++c) {
      const double k = kTwoPi / wavelength_m(freqs[c]);
      const double d = (tag - centre).norm();
      std::complex<double> h = std::polar(1.0, -k * d);
      if (hw.wall_gamma != 0.0) {
        const Vec3 image(tag.x(), 2.0 * hw.wall_y_m - tag.y(), tag.z());
        h += hw.wall_gamma * std::polar(1.0, -k * (image - centre).norm());
      }
      const double geometric = -std::arg(h * h);
      for (int r = 0; r < hw.reads_per_stop; ++r) {
        double phase = hw.tag_offset_rad + hw.truth.carrier_offsets_rad[c] + geometric + pattern + hw.noise_rad * gauss(rng);
        if (hw.outlier_fraction > 0.0 && uni(rng) < hw.outlier_fraction) phase = kTwoPi * uni(rng);
        if (hw.fold_pi && uni(rng) < 0.5) phase += kPi;
        out.groups[c].reads.push_back(PhaseRead{t, s.position, s.orientation, wrap_to_2pi(phase)});
        t += 0.001;
      }
    }
    t += 0.1;
  }
  return out;
}

// A plausible reader + antenna: chain offsets, a 3 cm / 1 cm phase-centre offset, a smooth pattern.
inline AntennaCalibration example_hardware() {
  AntennaCalibration h;
  h.antenna = "a0";
  h.frequencies_hz = adarf_carriers_hz();
  h.carrier_offsets_rad = {0.0, 1.1, -2.0, 0.4, 2.9, -0.7, 1.8, -2.6};
  h.phase_centre_offset_m = Vec3(0.03, 0.01, 0.0);
  h.pattern_rad = {0.2, 0.0, 0.6, 0.0, 0.0};
  return h;
}

}  // namespace rfidray::loc::testing
