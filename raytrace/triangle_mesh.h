#pragma once
// A triangle soup with per-triangle material names: what every scene loader (OBJ, SDF world, generator)
// produces and what the Embree scene is built from.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry.h"

namespace rfidray {

struct TriangleMesh {
  std::string name;                               // object / model / link name, for material overrides
  std::vector<Vec3> vertices;                     // metres, world frame once placed
  std::vector<std::array<uint32_t, 3>> triangles; // indices into vertices
  std::vector<uint32_t> triangle_material;        // per triangle: index into material_names
  std::vector<std::string> material_names;        // radio material names (usemtl names, or mapped)

  size_t triangle_count() const { return triangles.size(); }
  // Adds `other` (its vertices, triangles and materials) to this mesh.
  void append(const TriangleMesh& other);
  // Applies scale (per axis, in the mesh frame) then the pose, in place.
  void transform(const Pose& pose, const Vec3& scale = Vec3::Ones());
  // Axis-aligned bounds; min > max when empty.
  std::pair<Vec3, Vec3> bounds() const;
};

}  // namespace rfidray
