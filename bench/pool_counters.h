#pragma once
// The ray tracer's per-thread counters (tl_rays_traced, tl_segments_culled, tl_mirror_points,
// tl_reflections_found, tl_plane_pairs_tried), summed over the caller and every
// thread of the OpenMP pool (its threads persist between regions) and reset: what the benchmarks report per link.
#include <omp.h>

#include <cstdint>
#include <utility>

#include "raytrace/covered_rects.h"
#include "raytrace/embree_scene.h"
#include "raytrace/path_finder.h"

namespace rfidray::bench {

// `local` returns the calling thread's counter (a thread_local: each pool thread must read its own).
inline uint64_t take_from_pool(uint64_t& (*local)()) {
  uint64_t sum = 0;
#pragma omp parallel reduction(+ : sum)
  { sum += std::exchange(local(), 0); }
  return sum + std::exchange(local(), 0);
}

// Rays traced since the last call.
inline uint64_t take_pool_rays() {
  return take_from_pool([]() -> uint64_t& { return tl_rays_traced; });
}

// Reflection candidates culled without a ray (raytrace/covered_rects.h) since the last call.
inline uint64_t take_pool_culled() {
  return take_from_pool([]() -> uint64_t& { return tl_segments_culled; });
}

// Single-reflection mirror points on a facet (each needs a visibility decision) since the last call.
inline uint64_t take_pool_mirror_points() {
  return take_from_pool([]() -> uint64_t& { return tl_mirror_points; });
}

// Single reflections found (both legs clear) since the last call.
inline uint64_t take_pool_reflections() {
  return take_from_pool([]() -> uint64_t& { return tl_reflections_found; });
}

// Double-bounce plane pairs tried (raytrace/path_finder.h) since the last call.
inline uint64_t take_pool_plane_pairs() {
  return take_from_pool([]() -> uint64_t& { return tl_plane_pairs_tried; });
}

}  // namespace rfidray::bench
