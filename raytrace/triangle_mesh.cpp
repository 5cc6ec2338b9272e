#include "raytrace/triangle_mesh.h"

#include <limits>

namespace rfidray {

void TriangleMesh::append(const TriangleMesh& other) {
  const auto vertex_offset = static_cast<uint32_t>(vertices.size());
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  // Map the other mesh's material indices onto ours, adding names we do not have yet.
  std::vector<uint32_t> remap(other.material_names.size());
  for (size_t i = 0; i < other.material_names.size(); ++i) {
    uint32_t found = static_cast<uint32_t>(material_names.size());
    for (size_t j = 0; j < material_names.size(); ++j)
      if (material_names[j] == other.material_names[i]) found = static_cast<uint32_t>(j);
    if (found == material_names.size()) material_names.push_back(other.material_names[i]);
    remap[i] = found;
  }
  for (size_t t = 0; t < other.triangles.size(); ++t) {
    const auto& tri = other.triangles[t];
    triangles.push_back({tri[0] + vertex_offset, tri[1] + vertex_offset, tri[2] + vertex_offset});
    triangle_material.push_back(remap[other.triangle_material[t]]);
  }
}

void TriangleMesh::transform(const Pose& pose, const Vec3& scale) {
  for (Vec3& v : vertices) v = pose.transform_point(v.cwiseProduct(scale));
  // A mirroring scale flips the winding; keep normals consistent with the geometry.
  if (scale.x() * scale.y() * scale.z() < 0.0)
    for (auto& tri : triangles) std::swap(tri[1], tri[2]);
}

std::pair<Vec3, Vec3> TriangleMesh::bounds() const {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo;
  for (const Vec3& v : vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  return {lo, hi};
}

}  // namespace rfidray
