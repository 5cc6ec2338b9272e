// Covered rectangles (raytrace/covered_rects.h): every rectangle is covered by the scene's triangles in its
// plane, none is found where coverage is not certain (holes, T-junctions, overlaps, noisy or tilted meshes),
// and blocks() is true only where Embree's occluded() is true — on random segments, segments ending on
// surfaces, and crossings next to rectangle edges.
#include <gtest/gtest.h>

#include <random>

#include <Eigen/Geometry>

#include "raytrace/covered_rects.h"
#include "raytrace/scene.h"
#include "raytrace/warehouse.h"

namespace rfidray {
namespace {

// Is (u, v) on a triangle of `meshes` lying in the plane x_axis = c (closed triangles, 1e-12 m slack)?
bool on_triangle_in_plane(const std::vector<TriangleMesh>& meshes, int axis, double c, double pu, double pv) {
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  for (const TriangleMesh& m : meshes)
    for (const auto& t : m.triangles) {
      const Vec3 &a = m.vertices[t[0]], &b = m.vertices[t[1]], &d = m.vertices[t[2]];
      if (a[axis] != c || b[axis] != c || d[axis] != c) continue;
      const auto side = [&](const Vec3& p, const Vec3& q) {
        return (q[u] - p[u]) * (pv - p[v]) - (q[v] - p[v]) * (pu - p[u]);
      };
      const double s0 = side(a, b), s1 = side(b, d), s2 = side(d, a);
      constexpr double kSlack = 1e-12;
      if ((s0 >= -kSlack && s1 >= -kSlack && s2 >= -kSlack) || (s0 <= kSlack && s1 <= kSlack && s2 <= kSlack))
        return true;
    }
  return false;
}

// Every rectangle, inflated by the margin, sampled on a 9 × 9 grid (corners included): each sample covered.
void expect_all_covered(const std::vector<TriangleMesh>& meshes, const CoveredRects& cr, const std::string& what) {
  const double m = cr.margin_m();
  for (const CoveredRects::Rect& r : cr.rects())
    for (int i = 0; i <= 8; ++i)
      for (int j = 0; j <= 8; ++j) {
        const double pu = r.lo_u - m + (r.hi_u - r.lo_u + 2 * m) * i / 8.0;
        const double pv = r.lo_v - m + (r.hi_v - r.lo_v + 2 * m) * j / 8.0;
        ASSERT_TRUE(on_triangle_in_plane(meshes, r.axis, r.c, pu, pv))
            << what << ": rectangle axis " << r.axis << " c " << r.c << " [" << r.lo_u << ", " << r.hi_u << "] × ["
            << r.lo_v << ", " << r.hi_v << "] not covered at (" << pu << ", " << pv << ")";
      }
}

// The scene's triangles as it holds them (float vertices about its local origin, widened to double): the
// geometry Embree traces and CoveredRects is built from.
std::vector<TriangleMesh> as_built(const Scene& scene) {
  std::vector<TriangleMesh> out;
  for (uint32_t g = 0; g < scene.meshes().size(); ++g) {
    const SceneMesh& m = scene.meshes()[g];
    TriangleMesh& t = out.emplace_back();
    t.name = m.name;
    for (size_t i = 0; i < m.vertex_count(); ++i) t.vertices.push_back(scene.vertex(g, i));
    t.triangles = m.triangles;
  }
  return out;
}

TriangleMesh named_mesh(const std::string& name) {
  TriangleMesh m;
  m.name = name;
  m.material_names = {"metal"};
  return m;
}

TEST(CoveredRects, EveryRectangleIsCovered) {
  for (int tess : {1, 2}) {
    WarehouseParams p;
    p.rows = 2, p.racks_per_row = 2, p.shelves = 3, p.tessellation = tess;
    const Scene scene(generate_warehouse(p), MaterialAssignment{});
    const CoveredRects cr(scene.meshes(), scene.local_origin());
    EXPECT_GT(cr.rect_count(), 50u);
    expect_all_covered(as_built(scene), cr, "warehouse tessellation " + std::to_string(tess));
  }
}

TEST(CoveredRects, NoneWhereCoverageIsUncertain) {
  // A 3 × 3 quad with one triangle removed (a hole), two coplanar quads meeting on an edge split 2 vs 3 times
  // (T-junctions), and two overlapping coplanar quads (covered twice: even parity, conservatively not used).
  TriangleMesh holed = named_mesh("holed");
  add_quad(holed, Vec3(0, 0, 0), Vec3(3, 0, 0), Vec3(0, 3, 0), 0, 3, 3);
  holed.triangles.erase(holed.triangles.begin() + 8);  // the centre quad's first triangle
  holed.triangle_material.pop_back();
  TriangleMesh tj = named_mesh("t-junction");
  add_quad(tj, Vec3(5, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), 0, 2, 2);
  add_quad(tj, Vec3(7, 0, 0), Vec3(2, 0, 0), Vec3(0, 2, 0), 0, 3, 3);
  TriangleMesh overlap = named_mesh("overlap");
  add_quad(overlap, Vec3(10, 0, 1), Vec3(2, 0, 0), Vec3(0, 2, 0), 0);
  add_quad(overlap, Vec3(11, 1, 1), Vec3(2, 0, 0), Vec3(0, 2, 0), 0);
  const Scene scene({holed, tj, overlap}, MaterialAssignment{});
  const std::vector<TriangleMesh> meshes = as_built(scene);  // integer corners: the same as given
  const CoveredRects cr(scene.meshes(), scene.local_origin());
  expect_all_covered(meshes, cr, "holes");
  for (const CoveredRects::Rect& r : cr.rects()) {
    ASSERT_EQ(r.axis, 2);
    // Nothing over the hole's triangle (centre quad [1, 2]², below its diagonal... either half: stay clear).
    const bool over_hole = r.c == 0.0 && r.hi_u > 1.0 && r.lo_u < 2.0 && r.hi_v > 1.0 && r.lo_v < 2.0 &&
                           !on_triangle_in_plane(meshes, 2, 0.0, 0.5 * (r.lo_u + r.hi_u), 0.5 * (r.lo_v + r.hi_v));
    EXPECT_FALSE(over_hole);
    // Nothing across the T-junction edge x = 7, nothing in the doubly covered square [11, 12]².
    if (r.c == 0.0) {
      EXPECT_FALSE(r.lo_u < 7.0 && r.hi_u > 7.0);
    }
    if (r.c == 1.0) {
      EXPECT_FALSE(r.lo_u < 12.0 && r.hi_u > 11.0 && r.lo_v < 2.0 && r.hi_v > 1.0);
    }
  }
  EXPECT_GT(cr.rect_count(), 0u);  // the rest of each is used
}

TEST(CoveredRects, NoneOnNoisyOrTiltedMeshes) {
  WarehouseParams p;
  p.rows = 1, p.racks_per_row = 2, p.shelves = 2;
  auto noisy = generate_warehouse(p);
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> noise(-1e-4, 1e-4);
  for (TriangleMesh& m : noisy)
    for (Vec3& v : m.vertices) v += Vec3(noise(rng), noise(rng), noise(rng));
  const Scene noisy_scene(noisy, MaterialAssignment{});
  EXPECT_EQ(CoveredRects(noisy_scene.meshes(), noisy_scene.local_origin()).rect_count(), 0u);
  TriangleMesh box = named_mesh("tilted box");
  add_box(box, Vec3(-1, -1, -1), Vec3(1, 1, 1), 0, 2);
  const Eigen::Matrix3d rot = (Eigen::AngleAxisd(0.3, Vec3::UnitX()) * Eigen::AngleAxisd(0.2, Vec3::UnitY())).toRotationMatrix();
  for (Vec3& v : box.vertices) v = rot * v + Vec3(0, 0, 3);
  const Scene box_scene({box}, MaterialAssignment{});
  EXPECT_EQ(CoveredRects(box_scene.meshes(), box_scene.local_origin()).rect_count(), 0u);
}

// blocks() ⇒ Embree occluded(), on `n` segments of each kind; returns how many blocks() decided.
size_t expect_blocks_sound(const Scene& scene, const CoveredRects& cr, std::mt19937_64& rng, int n) {
  // Plain variables, not a structured binding: lambdas below capture them (clang 14 cannot capture bindings).
  const Vec3 lo = scene.bounds_lo(), hi = scene.bounds_hi();
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto inside = [&] { return Vec3(lo.x() + u(rng) * (hi.x() - lo.x()), lo.y() + u(rng) * (hi.y() - lo.y()),
                                        lo.z() + u(rng) * (hi.z() - lo.z())); };
  const std::vector<CoveredRects::Rect> rects = cr.rects();
  // A point on a random rectangle's plane: inside it, or within ±2 margins of one of its edges.
  const auto on_rect = [&](bool near_edge) {
    const CoveredRects::Rect& r = rects[static_cast<size_t>(u(rng) * rects.size())];
    Vec3 q;
    q[r.axis] = r.c;
    double pu = r.lo_u + u(rng) * (r.hi_u - r.lo_u), pv = r.lo_v + u(rng) * (r.hi_v - r.lo_v);
    if (near_edge) {
      const double off = (u(rng) - 0.5) * 4.0 * cr.margin_m();
      (u(rng) < 0.5 ? pu : pv) = u(rng) < 0.5 ? (u(rng) < 0.5 ? r.lo_u : r.hi_u) + off : (u(rng) < 0.5 ? r.lo_v : r.hi_v) + off;
    }
    q[(r.axis + 1) % 3] = pu, q[(r.axis + 2) % 3] = pv;
    return q;
  };
  size_t decided = 0;
  for (int kind = 0; kind < 4; ++kind)
    for (int i = 0; i < n; ++i) {
      Vec3 a = inside(), b = inside();
      double t0 = 1e-3, t1_cut = 1e-3;
      if (kind == 1) b = on_rect(false), t1_cut = 1e-4 * u(rng);      // ends on a surface (a tag on a shelf)
      if (kind == 2) a = on_rect(false), t0 = 1e-4 * u(rng);          // starts on one (a reflection point)
      if (kind == 3) {                                                 // crosses next to a rectangle's edge
        const Vec3 q = on_rect(true);
        const Vec3 d = Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5).normalized();
        a = q - (0.5 + 3 * u(rng)) * d, b = q + (0.5 + 3 * u(rng)) * d;
      }
      const double len = (b - a).norm();
      if (!(len > 1e-2)) continue;
      const Vec3 d = (b - a) / len;
      const double t1 = len - t1_cut;
      if (cr.blocks(a, d, t0, t1)) {
        ++decided;
        EXPECT_TRUE(scene.bvh().occluded(a, d, t0, t1))
            << "kind " << kind << " from (" << a.transpose() << ") dir (" << d.transpose() << ") t " << t0 << "…" << t1;
      }
    }
  return decided;
}

TEST(CoveredRects, BlocksOnlyWhatEmbreeBlocks) {
  std::mt19937_64 rng(17);
  for (int tess : {1, 2}) {
    WarehouseParams p;
    p.rows = 3, p.racks_per_row = 3, p.shelves = 4, p.tessellation = tess;
    const auto scene = std::make_shared<const Scene>(generate_warehouse(p), MaterialAssignment{});
    const CoveredRects cr(scene->meshes(), scene->local_origin());
    EXPECT_GT(expect_blocks_sound(*scene, cr, rng, 3000), 1000u) << "tessellation " << tess;
  }
  // Crossings exactly at the inner vertices and edge midpoints of tessellated faces (3 × 3 per face): the
  // culling counts on Embree's robust mode hitting a covered point there (its edge functions of neighbouring
  // triangles are exact negatives, vertices get a ulp tolerance), as the exhaustive search's legs do.
  {
    WarehouseParams p;
    p.rows = 2, p.racks_per_row = 2, p.shelves = 3, p.tessellation = 3;
    const auto scene = std::make_shared<const Scene>(generate_warehouse(p), MaterialAssignment{});
    const CoveredRects cr(scene->meshes(), scene->local_origin());
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    size_t decided = 0;
    for (const SceneMesh& m : scene->meshes())
      for (size_t t = 0; t < m.triangles.size(); t += 3)
        for (int j = 0; j < 3; ++j) {
          const Vec3 a = m.local_vertex(m.triangles[t][j]) + scene->local_origin();
          const Vec3 b = m.local_vertex(m.triangles[t][(j + 1) % 3]) + scene->local_origin();
          for (const Vec3& q : {a, Vec3(0.5 * (a + b))}) {
            const Vec3 d = Vec3(u(rng), u(rng), u(rng)).normalized();
            const Vec3 o = q - 1.5 * d;
            if (cr.blocks(o, d, 1e-3, 3.0 - 1e-3)) {
              ++decided;
              EXPECT_TRUE(scene->bvh().occluded(o, d, 1e-3, 3.0 - 1e-3)) << "through (" << q.transpose() << ")";
            }
          }
        }
    EXPECT_GT(decided, 1000u) << "vertices and edges";
  }
  // A scene far from the world origin (Embree works relative to the local origin; the margins follow).
  WarehouseParams p;
  p.rows = 2, p.racks_per_row = 2, p.shelves = 3;
  auto meshes = generate_warehouse(p);
  for (TriangleMesh& m : meshes)
    for (Vec3& v : m.vertices) v += Vec3(4.5e5, 5.3e6, 120.0);
  const auto scene = std::make_shared<const Scene>(std::move(meshes), MaterialAssignment{});
  const CoveredRects cr(scene->meshes(), scene->local_origin());
  EXPECT_GT(expect_blocks_sound(*scene, cr, rng, 2000), 300u) << "georeferenced";
}

}  // namespace
}  // namespace rfidray
