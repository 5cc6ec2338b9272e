#pragma once
// The ray-traced channel: h = Σ_paths coefficient_i · λ/(4πL_i) · e^{−jkL_i} over the paths PathFinder finds
// (raytrace/path_finder.h documents the physics). Levels: los, los+blocked, single-bounce.
// Thread-safe: the scene is read-only and every call keeps its scratch on the calling thread.
//
// one_way (one antenna pose, many tags) is the batch entry point; what it does per pose is proportional to
// the pose's tags, not to the scene:
//   - the tags are traced in Morton order (coherent rays, warm caches); the order is cached per calling
//     thread and reused while the tags' Morton keys do not change (a robot's poses over static tags);
//   - the tags are spread over up to omp_get_max_threads() threads with oneTBB's work-stealing parallel_for
//     (serial inside an OpenMP parallel region, e.g. simulate's antenna loop). Not an OpenMP team: an OpenMP
//     parallel region ends in a barrier that waits for every thread of the team, and on a machine where
//     another process holds a core a descheduled team thread stalls every pose by a scheduler tick (4–8 ms
//     per pose measured on the 2-core machine, whatever the tag count); work stealing waits only for chunks
//     that another thread actually took, so a busy machine degrades to the calling thread's own speed;
//   - at level los, when TraceOptions::los_packets_by_timing is set (off by default: determinism, see there),
//     the visibility rays go in packets of the width that is fastest on this scene
//     (rtcOccluded1/4/8/16), chosen once per channel by timing each width on the first pose's rays: packets
//     win several times on small open scenes with short coherent rays and lose on big warehouses with long,
//     mostly blocked ones (bench_rays), and where the crossover lies depends on the scene and the CPU, so no
//     constant would do. Packets are taken only when ≥ 1.25× faster than single rays, so a scene near the
//     crossover stays with single rays run after run. Embree's packet and single-ray kernels agree except on
//     near-degenerate rays (in a triangle's plane, or grazing a surface's edge, to float precision;
//     raytrace/embree_scene.h): segments parallel to a coordinate plane are traced alone with rtcOccluded1
//     (PathFinder::trace_sum), and for any other such link the result follows the width chosen, so it can
//     differ between runs (none did on 10 M bench links: bench_rays --compare-widths). Packets are the
//     serial loop's at any thread count (chunks aligned to 16 tags).
#include <atomic>
#include <memory>
#include <mutex>

#include "core/channel.h"
#include "raytrace/edge_proximity.h"
#include "raytrace/path_finder.h"

namespace rfidray {

class RaytracedChannel final : public Channel {
 public:
  RaytracedChannel(std::shared_ptr<const Scene> scene, const TraceOptions& options = {});

  std::string name() const override { return to_string(finder_.options().level); }
  std::vector<Path> paths(const Endpoint& antenna, const Endpoint& tag, double frequency_hz) const override;
  // One candidate search per call (per antenna pose), shared by all tags; threads over tags when not inside
  // an OpenMP parallel region.
  void one_way(const Endpoint& antenna, std::span<const Endpoint> tags, double frequency_hz,
               std::span<std::complex<double>> h) const override;
  // 64 up to single-bounce, 17 (two chunks of 16 tags) from double-bounce up (raytraced_channel.cpp).
  size_t threaded_batch_min_tags() const override;

  // The nearest facet of the scene (Scene::nearest_surface) with its radio material.
  std::optional<NearbySurface> nearest_surface(const Vec3& point, double max_distance_m) const override;
  // The nearest edge (raytrace/edge_proximity.h) and how `end` sees it lit from `other_end`; the index is built on
  // the first call (edges extracted then when the level has none); distances up to 0.75 m are answered.
  std::optional<EdgeSight> nearest_edge(const Endpoint& end, const Endpoint& other_end,
                                        double max_distance_m) const override;
  // Narrow obstacles, slab crossings and parallel plates of the link (raytrace/obstacle_finder.h), with the same
  // edge index; one Embree ray and a few index queries. At the diffracting levels also the link's most uncertain
  // edge end (raytrace/edge_end_finder.h): one pass over the edges.
  ObstacleSight obstacle_sight(const Endpoint& antenna, const Endpoint& tag, double frequency_hz) const override;

  const PathFinder& finder() const { return finder_; }
  const Scene& scene() const { return finder_.scene(); }
  // The packet width of level los's visibility rays (1, 4, 8 or 16): 1 unless los_packets_by_timing, then 0
  // until the first batch of ≥ 64 tags has measured it. set_los_packet_width fixes it instead (tests,
  // benchmarks); throws std::invalid_argument for another width.
  int los_packet_width() const { return los_packet_width_.load(std::memory_order_relaxed); }
  void set_los_packet_width(int width);

 private:
  PathFinder finder_;
  mutable std::atomic<int> los_packet_width_{0};
  const EdgeProximity& edge_index() const;  // built on the first call
  mutable std::once_flag edge_index_once_;
  mutable std::unique_ptr<EdgeProximity> edge_index_;
};

// The fastest of widths 1, 4, 8, 16 for `finder`'s level-los visibility rays from `antenna` to `tags`
// (at most the first 512; best of 5 timings each, interleaved; a packet width only when ≥ 1.25× faster than
// single rays). Rays traced here are not counted in tl_rays_traced.
int fastest_los_packet_width(const PathFinder& finder, const Endpoint& antenna, std::span<const Endpoint> tags,
                             std::span<const uint32_t> order);

}  // namespace rfidray
