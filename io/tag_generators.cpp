#include "io/tag_generators.h"

#include "core/memory_budget.h"

#include <fnmatch.h>

#include <cmath>

#include "core/error.h"
#include "core/limits.h"
#include "core/units.h"
#include "core/number_text.h"

namespace rfidray::io {
namespace {

// Memory one grid point costs downstream (its position, a tag or cell pose, coverage's per-cell results),
// checked against the memory budget before a grid is allocated: 224 bytes measured (peak RSS of a coverage map of
// the paper warehouse at 36 k and 576 k cells); the estimate rounds up.
constexpr double kBytesPerGridPoint = 256.0;

std::string count_text(double n) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.0f", n);
  return buf;
}

bool matches(const std::string& pattern, const std::string& name) {
  return pattern.empty() || fnmatch(pattern.c_str(), name.c_str(), 0) == 0;
}

// The in-plane basis of a facet: u horizontal (world Z × n), v = n × u (up); for horizontal facets u = world X.
void plane_basis(const Vec3& n, Vec3& u, Vec3& v) {
  u = Vec3::UnitZ().cross(n);
  if (u.norm() < 1e-6) u = Vec3::UnitX() - n * n.x();
  u.normalize();
  v = n.cross(u);
}

}  // namespace

Quat surface_orientation(const Vec3& n) {
  Vec3 u, v;
  plane_basis(n, u, v);
  Eigen::Matrix3d r;
  r.col(0) = n;  // local X: the normal
  r.col(1) = u;  // local Y
  r.col(2) = v;  // local Z: up in the plane (n × u = v: right-handed)
  return Quat(r).normalized();
}

std::vector<Vec3> grid_points(const TagGrid& grid, const std::string& field, size_t max_points,
                              std::array<size_t, 3>* counts) {
  if (!(std::isfinite(grid.step_m) && grid.step_m > 0.0))
    throw field_error(field + ".step_m", "must be > 0 (got " + num(grid.step_m) + ")");
  std::array<size_t, 3> n{};
  double total = 1.0;
  for (int k = 0; k < 3; ++k) {
    if (!(limits::coordinate_ok(grid.min[k]) && limits::coordinate_ok(grid.max[k])))
      throw field_error(field, "corners must be finite coordinates within ±" + num(limits::kMaxCoordinateM) + " m");
    const double span = grid.max[k] - grid.min[k];
    if (span < 0.0)
      throw field_error(field + ".max", "must be ≥ min on every axis (axis " + std::string(1, "xyz"[k]) + ": " +
                                            num(grid.min[k]) + " > " + num(grid.max[k]) + ")");
    // The last point is kept when it falls within a millionth of a step of max (rounding of e.g. 0.1 steps).
    const double cells = std::floor(span / grid.step_m + 1e-6) + 1.0;
    total *= cells;
    if (total > static_cast<double>(max_points))
      throw field_error(field, "would hold more than " + count_text(static_cast<double>(max_points)) +
                                   " points (step " + num(grid.step_m) + " m); use a larger step or a smaller box");
    n[k] = static_cast<size_t>(cells);
  }
  // What a point costs downstream (its position, a pose, the per-cell results of coverage), checked before
  // anything is allocated against the memory budget (core/memory_budget.h).
  check_memory_estimate(total * kBytesPerGridPoint, "field '" + field + "': " + count_text(total) + " points",
                        std::to_string(static_cast<int>(kBytesPerGridPoint)) + " bytes per point");
  if (counts) *counts = n;
  std::vector<Vec3> out;
  out.reserve(n[0] * n[1] * n[2]);
  for (size_t iz = 0; iz < n[2]; ++iz)
    for (size_t iy = 0; iy < n[1]; ++iy)
      for (size_t ix = 0; ix < n[0]; ++ix)
        out.emplace_back(grid.min.x() + static_cast<double>(ix) * grid.step_m,
                         grid.min.y() + static_cast<double>(iy) * grid.step_m,
                         grid.min.z() + static_cast<double>(iz) * grid.step_m);
  return out;
}

std::string tag_name(const std::string& pattern, size_t i, size_t ix, size_t iy, size_t iz) {
  std::string p = pattern;
  if (p.find("{i}") == std::string::npos && p.find("{ix}") == std::string::npos) p += "_{i}";
  const std::pair<const char*, size_t> keys[] = {{"{i}", i}, {"{ix}", ix}, {"{iy}", iy}, {"{iz}", iz}};
  for (const auto& [key, value] : keys) {
    const std::string k = key, v = std::to_string(value);
    for (size_t at = p.find(k); at != std::string::npos; at = p.find(k, at + v.size())) p.replace(at, k.size(), v);
  }
  return p;
}

std::vector<TagSpec> generate_tags(const TagSetSpec& set, const Scene* scene, size_t max_tags) {
  std::vector<TagSpec> out;
  auto make = [&](const std::string& name, const Vec3& p, const Quat& q) {
    TagSpec t;
    t.tag = set.tag;
    t.tag.name = name;
    t.motion.kind = MotionSpec::Kind::kFixed;
    t.motion.pose = Pose{p, q};
    t.source_line = set.source_line;
    out.push_back(std::move(t));
  };
  if (set.grid) {
    std::array<size_t, 3> n{};
    const std::vector<Vec3> pts = grid_points(*set.grid, set.field + ".grid", max_tags, &n);
    for (size_t i = 0; i < pts.size(); ++i)
      make(tag_name(set.name_pattern, i, i % n[0], (i / n[0]) % n[1], i / (n[0] * n[1])), pts[i], set.orientation);
    return out;
  }
  if (!set.surface) throw field_error(set.field, "needs one of 'grid' and 'surface'");
  if (!scene) throw field_error(set.field + ".surface", "surface tags need the scenario's scene (scene.meshes)");
  const SurfaceSelection& s = *set.surface;
  const std::string field = set.field + ".surface";
  if (!(std::isfinite(s.step_m) && s.step_m > 0.0))
    throw field_error(field + ".step_m", "must be > 0 (got " + num(s.step_m) + ")");
  if (!(std::isfinite(s.offset_m) && std::abs(s.offset_m) <= 100.0))
    throw field_error(field + ".offset_m", "must be within ±100 m (got " + num(s.offset_m) + ")");
  Vec3 facing = Vec3::Zero();
  if (s.facing) {
    if (!(s.facing->allFinite() && s.facing->norm() > 0.0)) throw field_error(field + ".facing", "must be a non-zero direction");
    facing = s.facing->normalized();
  }
  const double cos_tol = std::cos(s.facing_tolerance_deg * kPi / 180.0);
  size_t selected = 0;
  const auto& facets = scene->facets();
  for (size_t f = 0; f < facets.size(); ++f) {
    const Facet& facet = facets[f];
    if (!matches(s.material, scene->materials()[facet.material].name)) continue;
    if (!matches(s.mesh, scene->meshes()[facet.mesh].name)) continue;
    if (s.facing && facet.normal.dot(facing) < cos_tol) continue;
    ++selected;
    const Vec3 n = facet.normal.normalized();
    Vec3 u, v;
    plane_basis(n, u, v);
    const Quat q = surface_orientation(n);
    // Lattice points every step_m in the plane's (u, v) coordinates, centred on the facet's extent (a strip
    // narrower than a step — a shelf's front edge, a post — gets one centred row), kept where a triangle of the
    // facet is (inclusive edges).
    struct Tri {
      double u[3], v[3], area;
    };
    std::vector<Tri> tris;
    double lo_u = INFINITY, hi_u = -INFINITY, lo_v = INFINITY, hi_v = -INFINITY, plane = 0.0;
    for (uint32_t tri : facet.triangles) {
      const auto c = scene->corners(tri);
      plane = n.dot(c[0]);
      Tri t;
      for (int k = 0; k < 3; ++k) {
        t.u[k] = u.dot(c[k]), t.v[k] = v.dot(c[k]);
        lo_u = std::min(lo_u, t.u[k]), hi_u = std::max(hi_u, t.u[k]);
        lo_v = std::min(lo_v, t.v[k]), hi_v = std::max(hi_v, t.v[k]);
      }
      t.area = (t.u[1] - t.u[0]) * (t.v[2] - t.v[0]) - (t.u[2] - t.u[0]) * (t.v[1] - t.v[0]);
      if (std::abs(t.area) > 1e-18) tris.push_back(t);
    }
    if (tris.empty()) continue;
    const double cols = std::floor((hi_u - lo_u) / s.step_m + 1e-9) + 1.0;
    const double rows = std::floor((hi_v - lo_v) / s.step_m + 1e-9) + 1.0;
    if (cols * rows + static_cast<double>(out.size()) > static_cast<double>(max_tags))
      throw field_error(set.field, "would generate more than " + count_text(double(max_tags)) + " tags; use a larger step_m");
    const double u0 = 0.5 * (lo_u + hi_u) - 0.5 * (cols - 1.0) * s.step_m;
    const double v0 = 0.5 * (lo_v + hi_v) - 0.5 * (rows - 1.0) * s.step_m;
    for (double b = 0; b < rows; ++b)
      for (double a = 0; a < cols; ++a) {
        const double pu = u0 + a * s.step_m, pv = v0 + b * s.step_m;
        bool inside = false;
        for (const Tri& t : tris) {
          const double w1 = ((pu - t.u[0]) * (t.v[2] - t.v[0]) - (t.u[2] - t.u[0]) * (pv - t.v[0])) / t.area;
          const double w2 = ((t.u[1] - t.u[0]) * (pv - t.v[0]) - (pu - t.u[0]) * (t.v[1] - t.v[0])) / t.area;
          if (w1 >= -1e-9 && w2 >= -1e-9 && w1 + w2 <= 1.0 + 1e-9) {
            inside = true;
            break;
          }
        }
        if (!inside) continue;
        const Vec3 at = pu * u + pv * v + (plane + s.offset_m) * n;
        if (s.within && ((at - s.within->first).minCoeff() < 0.0 || (s.within->second - at).minCoeff() < 0.0)) continue;
        make(tag_name(set.name_pattern, out.size()), at, q);
      }
  }
  if (selected == 0)
    throw field_error(field, "selects no surface of the scene (material '" + s.material + "', mesh '" + s.mesh +
                                 "'" + (s.facing ? ", facing" : "") + ")");
  return out;
}

}  // namespace rfidray::io
