#include "raytrace/raytraced_channel.h"

#include <omp.h>

#include <algorithm>

#include "raytrace/morton.h"

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
  // The caller's scratch, reused across calls (bitmaps cleared, not reallocated, per pose). Bound to plain
  // references: inside the parallel region a thread_local name would denote each worker's own copy.
  thread_local PoseCandidates tl_candidates;
  thread_local std::vector<std::pair<uint64_t, uint32_t>> tl_order;
  PoseCandidates& candidates = tl_candidates;
  std::vector<std::pair<uint64_t, uint32_t>>& order = tl_order;
  finder_.prepare_pose(antenna.pose.position, candidates);
  const auto n = static_cast<std::ptrdiff_t>(tags.size());
  // Tags in spatial (Morton) order, so consecutive links traverse the same part of the BVH and hit warm
  // caches; every link is computed on its own, so the order changes nothing but speed.
  order.resize(tags.size());
  for (size_t i = 0; i < tags.size(); ++i) order[i] = {morton_key(tags[i].pose.position), static_cast<uint32_t>(i)};
  std::sort(order.begin(), order.end());
  // Exceptions must not leave an OpenMP region: keep the first and rethrow after the loop.
  std::exception_ptr error;
#pragma omp parallel for schedule(dynamic, 16) if (n >= 64 && !omp_in_parallel())
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    try {
      const uint32_t k = order[i].second;
      auto& traced = scratch_paths();
      finder_.trace(antenna, tags[k], frequency_hz, candidates, traced);
      std::complex<double> sum{0.0, 0.0};
      for (const TracedPath& p : traced) sum += p.contribution;
      h[k] = sum;
    } catch (...) {
#pragma omp critical(rfidray_raytrace_error)
      if (!error) error = std::current_exception();
    }
  }
  if (error) std::rethrow_exception(error);
}

}  // namespace rfidray
