#pragma once
// Module raytrace — owns scenes (meshes, facets, the Embree BVH), mesh loading and generated warehouses, and
// the path finder behind the traced channel levels. Includes core/ only; the one Embree boundary is
// raytrace/embree_scene.h.
//
// A static radio scene: triangle meshes with resolved radio materials, their planar facets, and one Embree
// BVH built once. Read-only after construction, so one Scene is shared by every thread and channel.
//
// Dynamic objects (moving obstacles) would be added as further Embree geometries in a second, rebuilt
// top-level scene referencing this one as an instance; everything here is addressed by (geomID, primID),
// which stays valid in that design.
#include <algorithm>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/material.h"
#include "core/scenario.h"
#include "raytrace/embree_scene.h"
#include "raytrace/facet.h"
#include "raytrace/material_map.h"
#include "raytrace/scene_mesh.h"
#include "raytrace/triangle_mesh.h"

namespace rfidray {

struct SceneOptions {
  FacetOptions facets;
  std::string embree_config;  // rtcNewDevice config ("" = Embree default)
};

class Scene {
 public:
  // Every vertex is first rounded to single precision about local_origin() (≤ 0.5 float ulp: 0.24 µm at 4 m
  // from it, 3.8 µm at 64 m), so that facets, the image method and Embree all see the same triangles; the
  // meshes' double vertices are not kept (SceneMesh). Antenna and tag positions stay double.
  Scene(std::vector<TriangleMesh> meshes, const MaterialAssignment& assignment, const SceneOptions& options = {});

  const std::vector<SceneMesh>& meshes() const { return meshes_; }
  const std::vector<RadioMaterial>& materials() const { return materials_; }
  const std::vector<Facet>& facets() const { return facets_; }
  const EmbreeScene& bvh() const { return *bvh_; }
  // Where the BVH and the vertex weld are centred: the bounding-box centre when the scene lies more than
  // kRecentreBeyondM from the world origin (georeferenced meshes), else the origin itself (scenes near it keep
  // their world coordinates, rounded to float). Queries always take world coordinates.
  const Vec3& local_origin() const { return origin_; }
  static constexpr double kRecentreBeyondM = 1e4;
  // Resident bytes per triangle of a built scene (meshes, facets, Embree's BVH; the float vertex and index
  // arrays are shared with Embree): 103–147 measured on the parametric warehouses of 0.1–5 M
  // triangles (0.89 vertices per triangle; README, #13 memory), plus a few MB fixed. Kept at 330, the upper end
  // measured before, so that meshes with unshared vertices (up to 3 per triangle: ~25 bytes more) fit too;
  // it is the estimate checked against the memory budget before a scene is built.
  static constexpr double kSceneBytesPerTriangle = 330.0;
  // Defaults applied and other remarks from material resolution, for the user.
  const std::vector<std::string>& notes() const { return notes_; }

  // Axis-aligned bounds of every vertex, world coordinates; lo > hi when the scene has no vertices.
  const Vec3& bounds_lo() const { return bounds_lo_; }
  const Vec3& bounds_hi() const { return bounds_hi_; }
  size_t triangle_count() const { return facet_of_triangle_.size(); }
  bool empty() const { return triangle_count() == 0; }
  // Global triangle id of an Embree hit.
  uint32_t triangle_id(uint32_t geom, uint32_t prim) const { return triangle_offset_[geom] + prim; }
  uint32_t facet_of(uint32_t triangle) const { return facet_of_triangle_[triangle]; }
  // The mesh a global triangle belongs to: its facet's, or for a triangle in no facet (degenerate), by binary
  // search of the meshes' first ids (no per-triangle table: 4 bytes per triangle).
  uint32_t mesh_of(uint32_t triangle) const {
    const uint32_t f = facet_of_triangle_[triangle];
    if (f != kNoFacet) return facets_[f].mesh;
    return static_cast<uint32_t>(std::upper_bound(triangle_offset_.begin(), triangle_offset_.end(), triangle) -
                                 triangle_offset_.begin()) - 1;
  }
  // Through the mesh's own per-triangle material names (not a second per-triangle table: 4 bytes per triangle).
  uint32_t material_of(uint32_t triangle) const {
    const uint32_t mesh = mesh_of(triangle);
    return material_slot_[slot_offset_[mesh] + meshes_[mesh].triangle_material[triangle - triangle_offset_[mesh]]];
  }
  // Unit normal of a triangle (zero for degenerate ones). Computed on demand (not stored: 24 bytes per
  // triangle); only the walk of a blocked direct path asks for it.
  Vec3 normal_of(uint32_t triangle) const {
    const auto c = corners(triangle);
    const Vec3 n = (c[1] - c[0]).cross(c[2] - c[0]);
    const double len = n.norm();
    return len > 0.0 ? Vec3(n / len) : Vec3::Zero();
  }
  // The three corners of a triangle, world coordinates (local origin + the float vertex, in double).
  std::array<Vec3, 3> corners(uint32_t triangle) const { return corners(mesh_of(triangle), triangle); }
  // The same, its mesh known (a facet's triangles: Facet::mesh). Inline: the exact reflection search's inner loop.
  std::array<Vec3, 3> corners(uint32_t mesh, uint32_t triangle) const {
    const SceneMesh& m = meshes_[mesh];
    const auto& tri = m.triangles[triangle - triangle_offset_[mesh]];
    return {origin_ + m.local_vertex(tri[0]), origin_ + m.local_vertex(tri[1]), origin_ + m.local_vertex(tri[2])};
  }
  // The surface nearest to `point` within `max_distance_m` (a tag's mount, core/tag_antenna.h): its distance,
  // global triangle and radio material; std::nullopt when none is that close.
  struct NearbySurface {
    double distance_m = 0.0;
    uint32_t triangle = 0;
    uint32_t material = 0;  // index into materials()
    double facet_extent_m = 1e300;  // the smaller in-plane size of its facet's bounds (no facet: infinity)
    bool faces_facet = true;        // the nearest point is the perpendicular foot, not on the facet's border
  };
  std::optional<NearbySurface> nearest_surface(const Vec3& point, double max_distance_m) const;
  // Vertex i of mesh `mesh`, world coordinates.
  Vec3 vertex(uint32_t mesh, size_t i) const { return origin_ + meshes_[mesh].local_vertex(i); }

 private:
  std::vector<SceneMesh> meshes_;
  std::vector<RadioMaterial> materials_;
  std::vector<uint32_t> triangle_offset_;       // per mesh
  std::vector<uint32_t> slot_offset_;           // per mesh: its first entry in material_slot_
  std::vector<uint32_t> material_slot_;         // per mesh and material name: index into materials_
  std::vector<uint32_t> facet_of_triangle_;     // global triangle → facet
  std::vector<Facet> facets_;
  std::vector<std::string> notes_;
  std::unique_ptr<EmbreeScene> bvh_;
  Vec3 origin_ = Vec3::Zero();
  Vec3 bounds_lo_ = Vec3::Constant(std::numeric_limits<double>::infinity()), bounds_hi_ = -bounds_lo_;
};

// One line per scene material whose ITU-R P.2040 fit is extrapolated at this frequency (several are specified
// from 1 GHz only; UHF RFID runs at 860–960 MHz), for the caller to print once.
std::vector<std::string> extrapolation_warnings(const Scene& scene, double frequency_hz);

// Loads OBJ files (their warnings are appended to `warnings` if given), resolves materials, builds the BVH.
std::shared_ptr<const Scene> load_scene(const std::vector<std::filesystem::path>& obj_files,
                                        const MaterialAssignment& assignment, const SceneOptions& options = {},
                                        std::vector<std::string>* warnings = nullptr);

// The scene of a scenario: each mesh file loaded, scaled and placed (MeshSpec::pose, scale), its material
// forced when MeshSpec::material is set, then the scenario's user materials, material_map and
// default_material applied. Errors name the scenario file and the mesh entry's line.
std::shared_ptr<const Scene> load_scene(const SceneSpec& spec, const std::string& scenario_source,
                                        const SceneOptions& options = {}, std::vector<std::string>* warnings = nullptr);

}  // namespace rfidray
