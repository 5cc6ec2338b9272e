#pragma once
// Planar facets: the connected sets of coplanar triangles of one mesh with one material. The image method
// reflects in a facet's plane; the facet's triangles say where the plane is actually there.
// Triangles are global ids: triangle_offset[mesh] + index within the mesh.
#include <cstdint>
#include <limits>
#include <vector>

#include "core/geometry.h"
#include "raytrace/triangle_mesh.h"

namespace rfidray {

inline constexpr uint32_t kNoFacet = std::numeric_limits<uint32_t>::max();

struct Facet {
  Vec3 normal = Vec3::UnitZ();  // unit; the plane is { x : normal·x = offset_m }
  double offset_m = 0.0;
  uint32_t mesh = 0;
  uint32_t material = 0;        // index into the scene's materials
  Vec3 lo = Vec3::Zero(), hi = Vec3::Zero();  // bounds of its triangles
  std::vector<uint32_t> triangles;            // global triangle ids
  double flatness_m = 0.0;                    // max distance of its vertices from the plane

  double signed_distance(const Vec3& p) const { return normal.dot(p) - offset_m; }
};

struct FacetOptions {
  // Two edge-adjacent triangles are merged when their normals differ by less than this angle and every
  // vertex lies within distance_tolerance_m of the facet's seed plane (no drift along curved surfaces).
  double angle_tolerance_rad = 1e-3;
  double distance_tolerance_m = 1e-4;
  double min_triangle_area_m2 = 1e-12;  // smaller triangles belong to no facet (they cannot be hit)
};

struct FacetSet {
  std::vector<Facet> facets;
  std::vector<uint32_t> facet_of_triangle;  // global triangle id → facet (kNoFacet for degenerate ones)
};

// `material_of_triangle[mesh][t]` is the resolved material index; `triangle_offset[mesh]` the global id of
// the mesh's first triangle.
FacetSet merge_facets(const std::vector<TriangleMesh>& meshes,
                      const std::vector<std::vector<uint32_t>>& material_of_triangle,
                      const std::vector<uint32_t>& triangle_offset, const FacetOptions& options = {},
                      const Vec3& origin = Vec3::Zero());  // vertices are welded relative to `origin`

}  // namespace rfidray
