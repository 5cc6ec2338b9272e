#pragma once
// Fills core/obstacle_sight.h for one link from the scene: one Embree ray along the direct segment (what blocks it
// first, and of which material) and a few queries of the edge index (raytrace/edge_proximity.h) at the two ends and
// at the blocking point. No path tracing: its cost is one ray and at most eight index queries per link.
//
//   - narrow obstacle: at an end (within `reach_m`) or at the blocking point, the two nearest edges are roughly
//     parallel (within 30°) and closer together than λ/2, and the direct segment is blocked there or passes the
//     nearer one within its first Fresnel zone radius;
//   - slab crossing: the direct segment's first hit is not a perfect conductor and the slab's nearest edge to the
//     crossing point (any indexed edge, else the crossed facet's bounding box) has a knife-edge ν ≤ 4.5 (its
//     diffracted field 0.225/ν ≥ 0.05 of the free-space one);
//   - parallel plates: an end's two nearest edges (within `reach_m`) belong to metal facets in parallel planes
//     (within 5°) λ/4 … 2λ apart, with the end between the planes.
// Units: metres, hertz. Thread-safe (reads only). Nothing throws for finite input; non-finite positions give an
// empty sight.
#include <cstdint>
#include <span>

#include "core/geometry.h"
#include "core/obstacle_sight.h"
#include "raytrace/edge_proximity.h"

namespace rfidray {

class Scene;

// `post_of_edge`: for each edge of the index, the thin post it belongs to when the level models posts
// (raytrace/thin_posts.h), or kNoPost; empty when it does not.
// An end this close (kρ to its nearest edge) to a thin post that the level models is in the post's near field,
// whether or not the post is near the direct line (core/obstacle_sight.h, NarrowObstacle::off_line).
inline constexpr double kModelledPostNearEndKrho = 4.0;

ObstacleSight find_obstacles(const Scene& scene, const EdgeProximity& edges, const Vec3& antenna, const Vec3& tag,
                             double frequency_hz, double reach_m, double surface_epsilon_m,
                             std::span<const uint32_t> post_of_edge = {});

}  // namespace rfidray
