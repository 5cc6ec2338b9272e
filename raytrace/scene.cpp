#include "raytrace/scene.h"

#include "core/memory_budget.h"

#include <cstdio>
#include <limits>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "core/error.h"
#include "core/limits.h"
#include "raytrace/obj_loader.h"
#include "core/number_text.h"

namespace rfidray {
namespace {

// One spare, zeroed element past the end, inside the capacity: Embree's 16-byte loads read past the last
// vertex and the last triangle of a shared buffer (rtcSetSharedGeometryBuffer(3)).
template <typename T>
void pad_for_embree(std::vector<T>& v) {
  if (v.capacity() == v.size()) v.reserve(v.size() + 1);
  v.push_back(T{});
  v.pop_back();
}

}  // namespace

Scene::Scene(std::vector<TriangleMesh> meshes, const MaterialAssignment& assignment, const SceneOptions& options) {
  // Every vertex finite and within the coordinate range (meshes come from files, transforms, SDF poses).
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  size_t total_triangles = 0;
  for (const TriangleMesh& m : meshes) {
    total_triangles += m.triangles.size();
    for (const Vec3& v : m.vertices) {
      if (!(limits::coordinate_ok(v.x()) && limits::coordinate_ok(v.y()) && limits::coordinate_ok(v.z())))
        throw InputError("mesh '" + clip(m.name) + "': vertex (" + num(v.x()) + ", " + num(v.y()) +
                         ", " + num(v.z()) + ") is outside ±" + num(limits::kMaxCoordinateM) +
                         " m (check its position, scale and pose)");
      lo = lo.cwiseMin(v);
      hi = hi.cwiseMax(v);
    }
  }
  if (double(total_triangles) > limits::kMaxTriangles || total_triangles >= kNoFacet)
    throw InputError("scene: " + std::to_string(total_triangles) + " triangles; at most " +
                     num(limits::kMaxTriangles));
  check_memory_estimate(double(total_triangles) * Scene::kSceneBytesPerTriangle,
                        "scene: " + std::to_string(total_triangles) + " triangles",
                        num(Scene::kSceneBytesPerTriangle) + " bytes per triangle: meshes, facets and the BVH");
  if (lo.x() <= hi.x()) {
    const Vec3 centre = 0.5 * (lo + hi);
    if (centre.cwiseAbs().maxCoeff() > kRecentreBeyondM) origin_ = centre;
  }
  ResolvedMaterials resolved = resolve_materials(meshes, assignment);
  materials_ = std::move(resolved.materials);
  notes_ = std::move(resolved.notes);
  uint32_t offset = 0;
  for (size_t m = 0; m < meshes.size(); ++m) {
    const TriangleMesh& mesh = meshes[m];
    triangle_offset_.push_back(offset);
    offset += static_cast<uint32_t>(mesh.triangles.size());
    // The resolved material of each of the mesh's material names (resolve_materials maps names, not triangles).
    slot_offset_.push_back(static_cast<uint32_t>(material_slot_.size()));
    material_slot_.resize(material_slot_.size() + mesh.material_names.size(), 0);
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
      material_slot_[slot_offset_.back() + mesh.triangle_material[t]] = resolved.per_triangle[m][t];
  }
  // Every vertex rounded to float about the local origin before anything is derived from it: the facets'
  // planes, bounds and flatness, the image method's corners and Embree's triangles are then one geometry
  // (corners() computes origin_ + float the same way, so a facet's bounds are its corners' bounds bitwise).
  // The float is computed once and kept: recomputing it from origin_ + float could round differently.
  std::vector<std::vector<float>> vertex_xyz(meshes.size());
  for (size_t mi = 0; mi < meshes.size(); ++mi) {
    std::vector<float>& xyz = vertex_xyz[mi];
    xyz.reserve(3 * meshes[mi].vertices.size() + 1);
    for (Vec3& v : meshes[mi].vertices) {
      for (int k = 0; k < 3; ++k) xyz.push_back(static_cast<float>(v[k] - origin_[k]));
      v = origin_ + Vec3(double(xyz[xyz.size() - 3]), double(xyz[xyz.size() - 2]), double(xyz[xyz.size() - 1]));
      bounds_lo_ = bounds_lo_.cwiseMin(v);
      bounds_hi_ = bounds_hi_.cwiseMax(v);
    }
    pad_for_embree(xyz);
  }
  FacetSet fs = merge_facets(meshes, resolved.per_triangle, triangle_offset_, options.facets, origin_);
  facets_ = std::move(fs.facets);
  facet_of_triangle_ = std::move(fs.facet_of_triangle);
  for (Facet& f : facets_) f.triangles.shrink_to_fit();  // grown one push_back at a time: up to 2× capacity
  // The scene's own meshes: float vertices (shared with Embree), the index arrays moved over and padded for
  // Embree. Each mesh's doubles are freed as it is converted.
  meshes_.reserve(meshes.size());
  for (size_t mi = 0; mi < meshes.size(); ++mi) {
    TriangleMesh& in = meshes[mi];
    SceneMesh& m = meshes_.emplace_back();
    m.name = std::move(in.name);
    m.vertex_xyz = std::move(vertex_xyz[mi]);
    std::vector<Vec3>().swap(in.vertices);
    m.triangles = std::move(in.triangles);
    pad_for_embree(m.triangles);
    m.triangle_material = std::move(in.triangle_material);
    m.material_names = std::move(in.material_names);
  }
  bvh_ = std::make_unique<EmbreeScene>(meshes_, options.embree_config, origin_);
  resolved.per_triangle = {};
#ifdef __GLIBC__
  // The build's temporaries (the vertex weld's hash nodes, the facets' triangle lists as they grew) are small
  // blocks that glibc keeps resident after free; hand whole free pages back (≈6 bytes per triangle on the
  // parametric warehouses). Moving the Scene later keeps Embree's shared index arrays valid (vector moves
  // keep their buffers; tests/raytrace/test_scene.cpp).
  malloc_trim(0);
#endif
}

std::optional<Scene::NearbySurface> Scene::nearest_surface(const Vec3& point, double max_distance_m) const {
  if (empty() || !bvh_) return std::nullopt;
  const NearestTriangle t = bvh_->nearest_triangle(point, max_distance_m, meshes_);
  if (!t.found) return std::nullopt;
  const uint32_t triangle = triangle_id(t.geom, t.prim);
  NearbySurface out{t.distance_m, triangle, material_of(triangle)};
  if (const uint32_t f = facet_of(triangle); f != kNoFacet) {
    // The facet's bounds along the world axes: the normal's axis is ~0 wide, the middle size is the in-plane
    // minimum for an axis-aligned facet (and a lower bound for a tilted one).
    Vec3 size = facets_[f].hi - facets_[f].lo;
    std::array<double, 3> v{size.x(), size.y(), size.z()};
    std::sort(v.begin(), v.end());
    out.facet_extent_m = v[1];
    out.faces_facet = std::abs(facets_[f].signed_distance(point)) >= 0.99 * t.distance_m;
  }
  return out;
}

std::vector<std::string> extrapolation_warnings(const Scene& scene, double frequency_hz) {
  std::vector<std::string> out;
  for (const RadioMaterial& m : scene.materials())
    if (!m.perfect_conductor && m.extrapolated(frequency_hz)) {
      char buf[200];
      std::snprintf(buf, sizeof buf, "material '%s': ITU-R P.2040 fit is specified from %g GHz; extrapolated to %g MHz",
                    m.name.c_str(), m.min_valid_ghz, frequency_hz / 1e6);
      out.push_back(buf);
    }
  return out;
}

std::shared_ptr<const Scene> load_scene(const std::vector<std::filesystem::path>& obj_files,
                                        const MaterialAssignment& assignment, const SceneOptions& options,
                                        std::vector<std::string>* warnings) {
  std::vector<TriangleMesh> meshes;
  for (const auto& f : obj_files) {
    ObjScene s = load_obj(f);
    if (warnings) warnings->insert(warnings->end(), s.warnings.begin(), s.warnings.end());
    for (auto& m : s.meshes) meshes.push_back(std::move(m));
  }
  return std::make_shared<const Scene>(std::move(meshes), assignment, options);
}

}  // namespace rfidray

namespace rfidray {

std::shared_ptr<const Scene> load_scene(const SceneSpec& spec, const std::string& scenario_source,
                                        const SceneOptions& options, std::vector<std::string>* warnings) {
  MaterialAssignment assignment;
  for (const MaterialSpec& m : spec.materials) {
    assignment.user_materials.push_back(user_material(m.name, m.relative_permittivity, m.conductivity_s_m, m.thickness_m));
    assignment.user_materials.back().solid = m.solid;
  }
  for (const MaterialMapEntry& e : spec.material_map) assignment.by_material[e.from] = e.to;
  assignment.default_material = spec.default_material;
  std::vector<TriangleMesh> meshes;
  for (size_t i = 0; i < spec.meshes.size(); ++i) {
    const MeshSpec& ms = spec.meshes[i];
    const std::string where = (scenario_source.empty() ? std::string() : scenario_source + ":" +
                               std::to_string(ms.source_line) + ": ") + "scene.meshes[" + std::to_string(i) + "]";
    ObjScene obj;
    try {
      obj = load_obj(ms.file);
      if (!ms.material.empty()) find_radio_material(ms.material, assignment.user_materials, where + ".material");
    } catch (const InputError& e) {
      throw InputError(where + ": " + e.what());
    }
    if (warnings) warnings->insert(warnings->end(), obj.warnings.begin(), obj.warnings.end());
    for (TriangleMesh& m : obj.meshes) {
      m.transform(ms.pose, ms.scale);
      if (!ms.material.empty()) {
        m.material_names = {ms.material};
        m.triangle_material.assign(m.triangles.size(), 0);
      }
      meshes.push_back(std::move(m));
    }
  }
  try {
    return std::make_shared<const Scene>(std::move(meshes), assignment, options);
  } catch (const InputError& e) {
    throw InputError((scenario_source.empty() ? std::string() : scenario_source + ": ") + "scene: " + e.what());
  }
}

}  // namespace rfidray
