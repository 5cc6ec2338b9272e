#pragma once
// A mesh as a built Scene holds it: the loader's TriangleMesh with its vertices in single precision about the
// scene's local origin (Scene::local_origin). This one vertex array is what Embree traces (shared with it, not
// copied) and what the image method reads, so both work on the same triangles to the last bit; the double
// vertices of the TriangleMesh are not kept (21 bytes per triangle on the parametric warehouses, README #13).
// Immutable once the Scene is built; any number of threads may read it.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "core/geometry.h"

namespace rfidray {

struct SceneMesh {
  std::string name;                               // object / model / link name, as in TriangleMesh
  // x, y, z per vertex, metres about the scene's local origin, then one spare float: Embree's 16-byte loads
  // read past the last vertex (rtcSetSharedGeometryBuffer(3)).
  std::vector<float> vertex_xyz;
  std::vector<std::array<uint32_t, 3>> triangles; // indices into the vertices; capacity > size (Embree's loads)
  std::vector<uint32_t> triangle_material;        // per triangle: index into material_names
  std::vector<std::string> material_names;

  size_t triangle_count() const { return triangles.size(); }
  size_t vertex_count() const { return vertex_xyz.size() / 3; }  // the spare float is not a vertex
  // Vertex i about the local origin (exactly the float Embree holds, widened).
  Vec3 local_vertex(size_t i) const {
    return {double(vertex_xyz[3 * i]), double(vertex_xyz[3 * i + 1]), double(vertex_xyz[3 * i + 2])};
  }
};

}  // namespace rfidray
