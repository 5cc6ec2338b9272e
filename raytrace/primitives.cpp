#include "raytrace/primitives.h"

#include <cmath>

#include "core/units.h"

namespace rfidray {
namespace {

TriangleMesh one_material(TriangleMesh m) {
  m.material_names = {""};
  m.triangle_material.assign(m.triangles.size(), 0);
  return m;
}

}  // namespace

TriangleMesh box_mesh(const Vec3& size) {
  TriangleMesh m;
  const Vec3 h = size / 2.0;
  for (int i = 0; i < 8; ++i)
    m.vertices.emplace_back(i & 1 ? h.x() : -h.x(), i & 2 ? h.y() : -h.y(), i & 4 ? h.z() : -h.z());
  // Two triangles per face, outward normals (vertex i has bit 0 = +x, bit 1 = +y, bit 2 = +z).
  m.triangles = {{0, 2, 3}, {0, 3, 1},   // −z
                 {4, 5, 7}, {4, 7, 6},   // +z
                 {0, 1, 5}, {0, 5, 4},   // −y
                 {2, 6, 7}, {2, 7, 3},   // +y
                 {0, 4, 6}, {0, 6, 2},   // −x
                 {1, 3, 7}, {1, 7, 5}};  // +x
  return one_material(std::move(m));
}

TriangleMesh cylinder_mesh(double radius, double length, int segments) {
  TriangleMesh m;
  const uint32_t n = static_cast<uint32_t>(segments);
  for (int cap = 0; cap < 2; ++cap)
    for (uint32_t k = 0; k < n; ++k) {
      const double a = kTwoPi * k / n;
      m.vertices.emplace_back(radius * std::cos(a), radius * std::sin(a), cap ? length / 2.0 : -length / 2.0);
    }
  for (uint32_t k = 0; k < n; ++k) {  // side: bottom k, k+1; top k, k+1
    const uint32_t k1 = (k + 1) % n;
    m.triangles.push_back({k, k1, n + k1});
    m.triangles.push_back({k, n + k1, n + k});
  }
  for (uint32_t k = 1; k + 1 < n; ++k) {  // caps: fans from vertex 0 of each ring
    m.triangles.push_back({0, k + 1, k});
    m.triangles.push_back({n, n + k, n + k + 1});
  }
  return one_material(std::move(m));
}

TriangleMesh sphere_mesh(double radius, int slices, int stacks) {
  TriangleMesh m;
  const uint32_t ns = static_cast<uint32_t>(slices), nt = static_cast<uint32_t>(stacks);
  m.vertices.emplace_back(0.0, 0.0, radius);  // north pole: 0
  for (uint32_t j = 1; j < nt; ++j) {         // rings 1 … stacks−1: 1 + (j−1)·slices + k
    const double polar = kPi * j / nt;
    for (uint32_t k = 0; k < ns; ++k) {
      const double az = kTwoPi * k / ns;
      m.vertices.emplace_back(radius * std::sin(polar) * std::cos(az), radius * std::sin(polar) * std::sin(az),
                              radius * std::cos(polar));
    }
  }
  const uint32_t south = static_cast<uint32_t>(m.vertices.size());
  m.vertices.emplace_back(0.0, 0.0, -radius);
  auto ring = [&](uint32_t j, uint32_t k) { return 1 + (j - 1) * ns + k % ns; };
  for (uint32_t k = 0; k < ns; ++k) m.triangles.push_back({0, ring(1, k), ring(1, k + 1)});
  for (uint32_t j = 1; j + 1 < nt; ++j)
    for (uint32_t k = 0; k < ns; ++k) {
      m.triangles.push_back({ring(j, k), ring(j + 1, k), ring(j + 1, k + 1)});
      m.triangles.push_back({ring(j, k), ring(j + 1, k + 1), ring(j, k + 1)});
    }
  for (uint32_t k = 0; k < ns; ++k) m.triangles.push_back({south, ring(nt - 1, k + 1), ring(nt - 1, k)});
  return one_material(std::move(m));
}

TriangleMesh plane_mesh(const Vec3& normal, double size_x, double size_y) {
  TriangleMesh m;
  const Quat q = Quat::FromTwoVectors(Vec3::UnitZ(), normal.normalized());
  for (const auto& [sx, sy] : {std::pair{-1, -1}, {1, -1}, {1, 1}, {-1, 1}})
    m.vertices.push_back(q * Vec3(sx * size_x / 2.0, sy * size_y / 2.0, 0.0));
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  return one_material(std::move(m));
}

}  // namespace rfidray
