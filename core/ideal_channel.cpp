#include <cmath>

#include "core/channel.h"
#include "core/error.h"

namespace rfidray {
namespace {

Path line_of_sight(const Endpoint& antenna, const Endpoint& tag, double frequency_hz) {
  if (!(std::isfinite(frequency_hz) && frequency_hz > 0.0))
    throw InputError("link: frequency must be finite and > 0 Hz (got " + std::to_string(frequency_hz) + ")");
  const Vec3 d = tag.pose.position - antenna.pose.position;
  const double length = d.norm();
  if (!(length > 0.0) || !std::isfinite(length))
    throw InputError("link: tag and antenna coincide or are not finite (distance " + std::to_string(length) + " m)");
  const Vec3 dir = d / length;
  Path p;
  p.kind = PathKind::kLineOfSight;
  p.length_m = length;
  p.point = antenna.pose.position;
  const double g_r = antenna.pattern.gain_linear_world(antenna.pose.orientation, dir);
  const double g_t = tag.pattern.gain_linear_world(tag.pose.orientation, -dir);
  p.coefficient = std::sqrt(g_r * g_t);
  p.contribution = path_contribution(length, p.coefficient, frequency_hz);
  return p;
}

}  // namespace

std::vector<Path> IdealChannel::paths(const Endpoint& antenna, const Endpoint& tag, double frequency_hz) const {
  return {line_of_sight(antenna, tag, frequency_hz)};
}

void IdealChannel::one_way(const Endpoint& antenna, std::span<const Endpoint> tags, double frequency_hz,
                           std::span<std::complex<double>> h) const {
  for (size_t i = 0; i < tags.size(); ++i) h[i] = line_of_sight(antenna, tags[i], frequency_hz).contribution;
}

}  // namespace rfidray
