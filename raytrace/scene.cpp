#include "raytrace/scene.h"

#include <cstdio>

#include "raytrace/obj_loader.h"

namespace rfidray {

Scene::Scene(std::vector<TriangleMesh> meshes, const MaterialAssignment& assignment, const SceneOptions& options)
    : meshes_(std::move(meshes)) {
  ResolvedMaterials resolved = resolve_materials(meshes_, assignment);
  materials_ = std::move(resolved.materials);
  notes_ = std::move(resolved.notes);
  uint32_t offset = 0;
  for (size_t m = 0; m < meshes_.size(); ++m) {
    triangle_offset_.push_back(offset);
    offset += static_cast<uint32_t>(meshes_[m].triangles.size());
    for (size_t t = 0; t < meshes_[m].triangles.size(); ++t) {
      triangle_mesh_.push_back(static_cast<uint32_t>(m));
      material_of_triangle_.push_back(resolved.per_triangle[m][t]);
      const auto& tri = meshes_[m].triangles[t];
      const auto& v = meshes_[m].vertices;
      const Vec3 c = (v[tri[1]] - v[tri[0]]).cross(v[tri[2]] - v[tri[0]]);
      const double len = c.norm();
      triangle_normal_.push_back(len > 0.0 ? Vec3(c / len) : Vec3::Zero());
    }
  }
  FacetSet fs = merge_facets(meshes_, resolved.per_triangle, triangle_offset_, options.facets);
  facets_ = std::move(fs.facets);
  facet_of_triangle_ = std::move(fs.facet_of_triangle);
  bvh_ = std::make_unique<EmbreeScene>(meshes_, options.embree_config);
}

std::array<Vec3, 3> Scene::corners(uint32_t triangle) const {
  const TriangleMesh& m = meshes_[triangle_mesh_[triangle]];
  const auto& tri = m.triangles[triangle - triangle_offset_[triangle_mesh_[triangle]]];
  return {m.vertices[tri[0]], m.vertices[tri[1]], m.vertices[tri[2]]};
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
