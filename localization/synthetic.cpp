#include "localization/synthetic.h"

#include <cmath>
#include <random>

#include "core/random.h"
#include "core/units.h"

namespace rfidray::loc {

std::vector<PathSample> sample_polyline(const std::vector<Vec3>& waypoints, double speed_m_s, double rate_hz,
                                        double antenna_yaw_rad) {
  std::vector<PathSample> out;
  if (waypoints.size() < 2 || speed_m_s <= 0.0 || rate_hz <= 0.0) return out;
  std::vector<double> cumulative{0.0};
  for (size_t i = 1; i < waypoints.size(); ++i)
    cumulative.push_back(cumulative.back() + (waypoints[i] - waypoints[i - 1]).norm());
  const double total = cumulative.back();
  const double dt = 1.0 / rate_hz;
  size_t seg = 1;
  for (long k = 0;; ++k) {
    const double t = k * dt;
    const double s = t * speed_m_s;
    if (s > total + 1e-12) break;
    while (seg + 1 < waypoints.size() && s > cumulative[seg]) ++seg;
    const double len = cumulative[seg] - cumulative[seg - 1];
    const double u = len > 0.0 ? (s - cumulative[seg - 1]) / len : 0.0;
    const Vec3 dir = waypoints[seg] - waypoints[seg - 1];
    PathSample p;
    p.time_s = t;
    p.position = waypoints[seg - 1] + u * dir;
    const double yaw = std::atan2(dir.y(), dir.x()) + antenna_yaw_rad;
    p.orientation = Quat(Eigen::AngleAxisd(yaw, Vec3::UnitZ()));
    out.push_back(p);
  }
  return out;
}

TagReads synthesize(const std::string& tag_name, const Vec3& tag_m, const std::vector<PathSample>& path,
                    const SyntheticSpec& spec) {
  TagReads out;
  out.tag = tag_name;
  const size_t channels = spec.frequencies_hz.size();
  for (size_t c = 0; c < channels; ++c) {
    ReadGroup g;
    g.antenna = spec.antenna;
    g.frequency_hz = spec.frequencies_hz[c];
    out.groups.push_back(g);
  }
  Rng rng = make_stream(spec.seed, {spec.stream});
  std::normal_distribution<double> noise(0.0, 1.0);
  for (const PathSample& s : path) {
    const size_t c = channels == 1 ? 0 : static_cast<size_t>(std::floor(s.time_s / spec.hop_dwell_s)) % channels;
    const double n = noise(rng);  // drawn for every tick so the noise does not depend on the read range
    const double d = (tag_m - s.position).norm();
    if (d > spec.read_range_m) continue;
    const double lambda = wavelength_m(spec.frequencies_hz[c]);
    const double offset = c < spec.phase_offsets_rad.size() ? spec.phase_offsets_rad[c] : 0.0;
    double phase = wrap_to_2pi(offset + 4.0 * kPi * d / lambda + spec.phase_noise_rad * n);
    if (spec.phase_bits > 0) {
      const double q = kTwoPi / std::ldexp(1.0, spec.phase_bits);
      phase = wrap_to_2pi(std::round(phase / q) * q);
    }
    if (spec.signed_phase) phase = wrap_to_pi(phase);
    out.groups[c].reads.push_back(PhaseRead{s.time_s, s.position, s.orientation, phase});
  }
  std::erase_if(out.groups, [](const ReadGroup& g) { return g.reads.empty(); });
  return out;
}

}  // namespace rfidray::loc
