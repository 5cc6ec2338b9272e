#include "raytrace/raytraced_channel.h"

#include <omp.h>

#include <algorithm>

namespace rfidray {
namespace {

// Per-thread scratch so the per-link loop does not allocate once warmed up.
std::vector<TracedPath>& scratch_paths() {
  thread_local std::vector<TracedPath> paths;
  return paths;
}

// Interleaved bits of the position on a 0.25 m grid (21 bits per axis, offset so negative coordinates sort).
uint64_t morton_key(const Vec3& p) {
  auto spread = [](double x) {
    uint64_t v = static_cast<uint64_t>(std::clamp(x / 0.25 + 1048576.0, 0.0, 2097151.0));
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
  };
  return spread(p.x()) | spread(p.y()) << 1 | spread(p.z()) << 2;
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
