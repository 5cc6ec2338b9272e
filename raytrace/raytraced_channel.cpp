#include "raytrace/raytraced_channel.h"

#include <omp.h>

namespace rfidray {
namespace {

// Per-thread scratch so the per-link loop does not allocate once warmed up.
std::vector<TracedPath>& scratch_paths() {
  thread_local std::vector<TracedPath> paths;
  return paths;
}

}  // namespace

RaytracedChannel::RaytracedChannel(std::shared_ptr<const Scene> scene, const TraceOptions& options)
    : finder_(std::move(scene), options) {}

std::vector<Path> RaytracedChannel::paths(const Endpoint& antenna, const Endpoint& tag, double frequency_hz) const {
  PoseCandidates candidates;
  finder_.prepare_pose(antenna.pose.position, candidates);
  std::vector<TracedPath> traced;
  finder_.trace(antenna, tag, frequency_hz, candidates, traced);
  std::vector<Path> out;
  out.reserve(traced.size());
  for (const TracedPath& p : traced) out.push_back(finder_.to_path(p));
  return out;
}

void RaytracedChannel::one_way(const Endpoint& antenna, std::span<const Endpoint> tags, double frequency_hz,
                               std::span<std::complex<double>> h) const {
  PoseCandidates candidates;
  finder_.prepare_pose(antenna.pose.position, candidates);
  const auto n = static_cast<std::ptrdiff_t>(tags.size());
  // Exceptions must not leave an OpenMP region: keep the first and rethrow after the loop.
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 16) if (n >= 64 && !omp_in_parallel())
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    try {
      auto& traced = scratch_paths();
      finder_.trace(antenna, tags[i], frequency_hz, candidates, traced);
      std::complex<double> sum{0.0, 0.0};
      for (const TracedPath& p : traced) sum += p.contribution;
      h[i] = sum;
    } catch (...) {
#pragma omp critical(rfidray_raytrace_error)
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace rfidray
