#pragma once
// Diffracting edges of a scene, extracted from its merged facets (raytrace/facet.h) for first-order UTD
// (core/utd.h, used by the path finder at level `full`).
//
// An edge is a straight piece of a facet's outline (a triangle edge used once inside its facet, vertices
// welded across all meshes on a 1 µm grid), merged with its collinear neighbours into maximal segments:
//  - shared by two facets that are not coplanar: a wedge. Its two faces split the space around the edge into
//    two angular regions, α (from face a to face b, turning about +direction) and 2π − α; at trace time the
//    region holding both antenna and tag is the wedge's exterior (exterior angle nπ). A closed solid's inside
//    region is never lit (its legs are occluded), so face normals need not be oriented consistently.
//  - used by one facet only, and lying on no other facet: the free edge of a sheet, a half-plane (n = 2).
//    A sheet that ends on another surface (a post standing on the floor) is a junction, not an edge.
//  - edges inside a flat facet, between coplanar facets, or shared by more than two facets: none.
// Thread safety: values only.
#include <cstdint>
#include <limits>
#include <vector>

#include "core/geometry.h"

namespace rfidray {

class Scene;

inline constexpr uint32_t kNoEdge = std::numeric_limits<uint32_t>::max();

struct Edge {
  Vec3 start = Vec3::Zero();
  Vec3 direction = Vec3::UnitZ();  // unit, along the edge
  double length_m = 0.0;
  uint32_t facet_a = 0;
  uint32_t facet_b = std::numeric_limits<uint32_t>::max();  // kNoFacet for a half-plane
  // Unit vectors in face a (b), perpendicular to the edge, pointing from the edge into the face.
  Vec3 into_a = Vec3::UnitX(), into_b = Vec3::UnitX();
  // Angle from into_a to into_b turning about +direction, in (0, 2π); 2π for a half-plane.
  double alpha_rad = 0.0;

  bool half_plane() const { return facet_b == std::numeric_limits<uint32_t>::max(); }
};

struct EdgeOptions {
  double flat_tolerance_rad = 1e-3;  // faces closer than this to coplanar make no edge
  double junction_tolerance_m = 1e-5;  // a free edge within this of another facet is a junction
};

// All edges of the scene, in a deterministic order.
std::vector<Edge> extract_edges(const Scene& scene, const EdgeOptions& options = {});

}  // namespace rfidray
