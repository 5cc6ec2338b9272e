#include "raytrace/warehouse.h"

#include "core/memory_budget.h"

#include <algorithm>
#include <cmath>
#include <iterator>

#include "core/error.h"
#include "core/limits.h"
#include "core/number_text.h"

namespace rfidray {

// Memory of a generated warehouse per triangle while it is built and written: 68 bytes measured (peak RSS of
// gen-warehouse at 141 k and 563 k triangles); the estimate rounds up.
constexpr double kGeneratedBytesPerTriangle = 70.0;
namespace {

uint32_t material_index(TriangleMesh& mesh, const std::string& name) {
  for (size_t i = 0; i < mesh.material_names.size(); ++i)
    if (mesh.material_names[i] == name) return static_cast<uint32_t>(i);
  mesh.material_names.push_back(name);
  return static_cast<uint32_t>(mesh.material_names.size() - 1);
}

TriangleMesh named(const std::string& name) {
  TriangleMesh m;
  m.name = name;
  return m;
}

}  // namespace

void add_quad(TriangleMesh& mesh, const Vec3& corner, const Vec3& u, const Vec3& v, uint32_t material, int nu, int nv) {
  const auto base = static_cast<uint32_t>(mesh.vertices.size());
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) mesh.vertices.push_back(corner + u * (double(i) / nu) + v * (double(j) / nv));
  const auto at = [&](int i, int j) { return base + static_cast<uint32_t>(j * (nu + 1) + i); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      mesh.triangles.push_back({at(i, j), at(i + 1, j), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i, j + 1)});
      mesh.triangle_material.push_back(material);
      mesh.triangle_material.push_back(material);
    }
}

void add_box(TriangleMesh& mesh, const Vec3& lo, const Vec3& hi, uint32_t material, int n, bool with_bottom) {
  const Vec3 d = hi - lo;
  const Vec3 X(d.x(), 0, 0), Y(0, d.y(), 0), Z(0, 0, d.z());
  // Outward normals (u × v points out).
  if (with_bottom) add_quad(mesh, lo, Y, X, material, n, n);  // bottom (−z)
  add_quad(mesh, lo + Z, X, Y, material, n, n);               // top (+z)
  add_quad(mesh, lo, X, Z, material, n, n);                   // −y
  add_quad(mesh, lo + Y, Z, X, material, n, n);               // +y
  add_quad(mesh, lo, Z, Y, material, n, n);                   // −x
  add_quad(mesh, lo + X, Y, Z, material, n, n);               // +x
}

TriangleMesh rack_mesh(const std::string& name, const RackSpec& s, const std::string& material) {
  TriangleMesh m = named(name);
  const uint32_t mat = material_index(m, material);
  const double x_near = s.front_x_m, x_far = s.front_x_m + s.facing * s.depth_m;
  const double x_lo = std::min(x_near, x_far), x_hi = std::max(x_near, x_far);
  const double y_lo = s.y_min_m, y_hi = s.y_min_m + s.length_m;
  for (double top : s.shelf_tops_m)
    add_box(m, Vec3(x_lo, y_lo, top - s.plate_thickness_m), Vec3(x_hi, y_hi, top), mat, s.tessellation);
  // Posts: 1 cm proud of the plates on the outside, 5 cm above the top shelf, standing on the floor (open bottom).
  double top = 0.0;
  for (double t : s.shelf_tops_m) top = std::max(top, t);
  const double p = s.post_size_m, proud = 0.01;
  const double xs[2][2] = {{x_lo - proud, x_lo - proud + p}, {x_hi + proud - p, x_hi + proud}};
  const double ys[2][2] = {{y_lo - proud, y_lo - proud + p}, {y_hi + proud - p, y_hi + proud}};
  for (const auto& x : xs)
    for (const auto& y : ys) add_box(m, Vec3(x[0], y[0], 0.0), Vec3(x[1], y[1], top + 0.05), mat, s.tessellation, false);
  return m;
}

std::vector<TriangleMesh> paper_warehouse_meshes() {
  std::vector<TriangleMesh> out;
  const double x0 = -8.0, x1 = 7.0, y0 = -13.0, y1 = 11.0, height = 5.0;
  TriangleMesh floor = named("floor");
  add_quad(floor, Vec3(x0, y0, 0), Vec3(x1 - x0, 0, 0), Vec3(0, y1 - y0, 0), material_index(floor, "concrete"));
  out.push_back(std::move(floor));
  TriangleMesh walls = named("walls");
  const uint32_t c = material_index(walls, "concrete");
  add_quad(walls, Vec3(x0, y0, 0), Vec3(0, 0, height), Vec3(0, y1 - y0, 0), c);  // west  x = −8
  add_quad(walls, Vec3(x1, y0, 0), Vec3(0, y1 - y0, 0), Vec3(0, 0, height), c);  // east  x = 7
  add_quad(walls, Vec3(x0, y0, 0), Vec3(x1 - x0, 0, 0), Vec3(0, 0, height), c);  // south y = −13
  add_quad(walls, Vec3(x0, y1, 0), Vec3(0, 0, height), Vec3(x1 - x0, 0, 0), c);  // north y = 11
  out.push_back(std::move(walls));
  // East row (tags 1–6 at x = 2.90, z = 2.05): a 0.8 m bay is left open around y = −4 for the fixed antenna
  // at (3.5, −4.0, 2.0), which looks out across the aisle from between two racks.
  const double east[][2] = {{-9.5, -7.5}, {-7.4, -5.4}, {-5.3, -4.4}, {-3.6, -1.1}, {-1.0, 1.0}};
  for (size_t i = 0; i < std::size(east); ++i) {
    RackSpec r;
    r.front_x_m = 2.95;
    r.facing = +1;
    r.y_min_m = east[i][0];
    r.length_m = east[i][1] - east[i][0];
    r.shelf_tops_m = {0.15, 1.05, 2.00, 2.95};
    out.push_back(rack_mesh("rack_east_" + std::to_string(i + 1), r));
  }
  // West row (tags 7–10 at x = −4.85, z = 1.85, y from −7.70 to 5.95): eight 2 m racks.
  for (int i = 0; i < 8; ++i) {
    RackSpec r;
    r.front_x_m = -4.90;
    r.facing = -1;
    r.y_min_m = -9.5 + 2.1 * i;
    r.length_m = 2.0;
    r.shelf_tops_m = {0.15, 1.00, 1.80, 2.70};
    out.push_back(rack_mesh("rack_west_" + std::to_string(i + 1), r));
  }
  return out;
}

std::vector<TriangleMesh> ground_and_wall_meshes() {
  std::vector<TriangleMesh> out;
  TriangleMesh ground = named("ground");
  add_quad(ground, Vec3(-10, -10, 0), Vec3(20, 0, 0), Vec3(0, 20, 0), material_index(ground, "concrete"));
  out.push_back(std::move(ground));
  TriangleMesh wall = named("wall");
  add_quad(wall, Vec3(5, -5, 0), Vec3(0, 10, 0), Vec3(0, 0, 3), material_index(wall, "concrete"));
  out.push_back(std::move(wall));
  return out;
}

namespace {

// The triangle count in floating point (no overflow for any int parameters).
double triangle_estimate(const WarehouseParams& p) {
  const double n2 = double(p.tessellation) * p.tessellation;
  return double(p.rows) * p.racks_per_row * (12.0 * p.shelves + 40.0) * n2 + 2 * n2 + (p.walls ? 8 * n2 : 0);
}

}  // namespace

void validate(const WarehouseParams& p) {
  if (p.rows < 1) throw field_error("rows", "must be ≥ 1 (got " + std::to_string(p.rows) + ")");
  if (p.racks_per_row < 1) throw field_error("racks_per_row", "must be ≥ 1 (got " + std::to_string(p.racks_per_row) + ")");
  if (p.shelves < 1) throw field_error("shelves", "must be ≥ 1 (got " + std::to_string(p.shelves) + ")");
  if (p.tessellation < 1 || p.tessellation > 1000)
    throw field_error("tessellation", "must be in 1…1000 (got " + std::to_string(p.tessellation) + ")");
  // Lengths: finite, and small enough that every vertex stays within the coordinate range.
  limits::check_range(p.rack_length_m, 0.2, 1e4, "rack_length_m", "m");
  limits::check_range(p.rack_depth_m, 0.2, 1e4, "rack_depth_m", "m");
  limits::check_range(p.shelf_spacing_m, 0.1, 1e3, "shelf_spacing_m", "m");
  limits::check_range(p.aisle_m, 1e-3, 1e4, "aisle_m", "m");
  const double tri = triangle_estimate(p);
  if (tri > limits::kMaxTriangles)
    throw field_error("size", "would generate about " + rounded_text(tri, 6) + " triangles (~" +
                                  rounded_text(tri * kGeneratedBytesPerTriangle / 1e9, 3) + " GB in memory); at most " +
                                  num(limits::kMaxTriangles) + " (rows × racks × (12·shelves + 40) × tessellation²)");
  check_memory_estimate(tri * kGeneratedBytesPerTriangle, "field 'size': about " + rounded_text(tri, 6) + " triangles",
                        num(kGeneratedBytesPerTriangle) + " bytes per generated triangle");
  const double extent = std::max({double(p.rows) * (p.rack_depth_m + p.aisle_m) + 2 * p.aisle_m,
                                  double(p.racks_per_row) * (p.rack_length_m + 0.1) + 2 * p.aisle_m,
                                  p.shelves * p.shelf_spacing_m + 1.0});
  if (!(extent <= limits::kMaxCoordinateM))
    throw field_error("size", "the warehouse would span " + num(extent) + " m; at most " +
                                  num(limits::kMaxCoordinateM) + " m");
}

size_t warehouse_triangle_count(const WarehouseParams& p) {
  validate(p);
  const size_t n2 = static_cast<size_t>(p.tessellation) * p.tessellation;
  const size_t per_rack = (12 * static_cast<size_t>(p.shelves) + 4 * 10) * n2;
  return static_cast<size_t>(p.rows) * p.racks_per_row * per_rack + 2 * n2 + (p.walls ? 8 * n2 : 0);
}

std::vector<TriangleMesh> generate_warehouse(const WarehouseParams& p) {
  validate(p);
  const double gap = 0.1;
  const double length_y = p.racks_per_row * (p.rack_length_m + gap) - gap;
  const double margin = p.aisle_m;
  const double x0 = -margin, x1 = p.rows * (p.rack_depth_m + p.aisle_m) + margin;
  const double y0 = -margin, y1 = length_y + margin;
  const double height = p.shelves * p.shelf_spacing_m + 1.0;
  const int n = p.tessellation;
  std::vector<TriangleMesh> out;
  TriangleMesh floor = named("floor");
  add_quad(floor, Vec3(x0, y0, 0), Vec3(x1 - x0, 0, 0), Vec3(0, y1 - y0, 0), material_index(floor, "concrete"), n, n);
  out.push_back(std::move(floor));
  if (p.walls) {
    TriangleMesh walls = named("walls");
    const uint32_t c = material_index(walls, "concrete");
    add_quad(walls, Vec3(x0, y0, 0), Vec3(0, 0, height), Vec3(0, y1 - y0, 0), c, n, n);
    add_quad(walls, Vec3(x1, y0, 0), Vec3(0, y1 - y0, 0), Vec3(0, 0, height), c, n, n);
    add_quad(walls, Vec3(x0, y0, 0), Vec3(x1 - x0, 0, 0), Vec3(0, 0, height), c, n, n);
    add_quad(walls, Vec3(x0, y1, 0), Vec3(0, 0, height), Vec3(x1 - x0, 0, 0), c, n, n);
    out.push_back(std::move(walls));
  }
  RackSpec spec;
  spec.facing = +1;
  spec.length_m = p.rack_length_m;
  spec.depth_m = p.rack_depth_m;
  spec.tessellation = n;
  spec.shelf_tops_m.clear();
  for (int s = 0; s < p.shelves; ++s) spec.shelf_tops_m.push_back(0.15 + s * p.shelf_spacing_m);
  for (int r = 0; r < p.rows; ++r) {
    // Row r: aisle at x ∈ [r·(d + a), r·(d + a) + a), racks from there.
    spec.front_x_m = r * (p.rack_depth_m + p.aisle_m) + p.aisle_m;
    TriangleMesh row = named("row_" + std::to_string(r + 1));
    for (int k = 0; k < p.racks_per_row; ++k) {
      spec.y_min_m = k * (p.rack_length_m + gap);
      row.append(rack_mesh("", spec));
    }
    out.push_back(std::move(row));
  }
  return out;
}

}  // namespace rfidray
