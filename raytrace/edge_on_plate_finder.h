#pragma once
// The edge-on plate check of core/obstacle_sight.h (EdgeOnPlate) for one link: among the scene's metal edges (the
// edge index's, so at every level) those whose closest approach to the direct segment lies within the first
// Fresnel zone radius √(λ d1 d2 / (d1 + d2)) there, the pairs that bound one facet, run within 30° of parallel, and
// are λ/2 or more apart along the line but less than λ/2 apart across it. Edges of a thin post the level models
// as a cylinder are left out (judged as narrow obstacles). Of several such pairs the one with the smallest
// across-separation is reported.
// Cost: the edge index's cells along the segment (EdgeProximity::edges_near_segment), a segment–segment distance
// for each edge found there, and the pairs among the few within the zone.
// Units: metres, hertz. Thread-safe (reads only); nothing throws for finite input; non-finite ends give nullopt.
#include <cstdint>
#include <optional>
#include <span>

#include "core/geometry.h"
#include "core/obstacle_sight.h"
#include "raytrace/edge_proximity.h"

namespace rfidray {

class Scene;

std::optional<EdgeOnPlate> find_edge_on_plate(const Scene& scene, const EdgeProximity& edges, const Vec3& antenna,
                                              const Vec3& tag, double frequency_hz,
                                              std::span<const uint32_t> post_of_edge = {});

}  // namespace rfidray
