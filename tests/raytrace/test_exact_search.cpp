// The exact single-bounce search (CandidateMode::kExact, no candidate rays) against the exhaustive image
// method (CandidateMode::kExhaustive: every facet's image point, point-in-triangle on its triangles, both legs
// traced with rtcOccluded1 — raytrace/path_finder.cpp reflections_exhaustive, kept deliberately plain as the
// reference). Exactness means the same set of paths (kind, material, point, length) and the same channel,
// |Δh|/|h| ≤ 1e-12, per path and summed, on:
//   random parametric warehouses, meshes with vertex noise (merged into fitted-plane facets), grazing incidence,
//   reflection points exactly on facet edges and vertices (inner edges of a facet, its outer boundary, a corner
//   shared with a perpendicular facet, two coplanar facets of different materials meeting on an edge), and an
//   obstacle moving through a link (the scene rebuilt at each position).
// Each comparison is made twice, the exact search without and with its covered-rectangle culling of blocked
// legs (raytrace/covered_rects.h), which must change the rays traced and nothing else.
// Every path is kept (drop_below_db = 400) so weak reflections are compared too, and each case checks that it
// exercised reflections at all.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/error.h"
#include "raytrace/raytraced_channel.h"
#include "raytrace/warehouse.h"

namespace rfidray {
namespace {

constexpr double kF = 866e6;

Endpoint endpoint(const Vec3& p, bool circular = false) {
  Endpoint e;
  e.pose.position = p;
  e.polarization.kind = circular ? PolarizationKind::kCircularRight : PolarizationKind::kLinear;
  e.polarization.axis_local = Vec3::UnitZ();
  return e;
}

struct Link {
  Vec3 antenna, tag;
};

// Reflection candidates the culled exact search rejected without a ray, over every expect_exact call.
uint64_t g_culled = 0;

// Compares the exact search, without and with covered-rectangle culling (TraceOptions::cull_covered), to the
// exhaustive one on every link; returns the number of reflections seen.
size_t expect_exact(const std::shared_ptr<const Scene>& scene, const std::vector<Link>& links,
                    const std::string& what, double drop_below_db = 400.0) {
  TraceOptions ref_o;
  ref_o.candidates = CandidateMode::kExhaustive;
  ref_o.drop_below_db = drop_below_db;
  TraceOptions fast_o = ref_o;
  fast_o.candidates = CandidateMode::kExact;
  TraceOptions cull_o = fast_o;  // the fast search with legs culled by covered rectangles (covered_rects.h)
  cull_o.cull_covered = true;
  const RaytracedChannel reference(scene, ref_o), fast(scene, fast_o), culled(scene, cull_o);
  size_t reflections = 0;
  for (size_t i = 0; i < 2 * links.size(); ++i) {
    const Link& link = links[i % links.size()];
    const bool cull = i >= links.size();
    const Endpoint a = endpoint(link.antenna, (i % links.size()) % 3 == 2), t = endpoint(link.tag);
    const uint64_t culled_before = tl_segments_culled;
    const std::vector<Path> want = reference.paths(a, t, kF), got = (cull ? culled : fast).paths(a, t, kF);
    g_culled += tl_segments_culled - culled_before;
    const std::string where = what + (cull ? " (culled)" : "") + ": link " + std::to_string(i % links.size()) + " antenna (" +
                              std::to_string(a.pose.position.x()) + ", " + std::to_string(a.pose.position.y()) +
                              ", " + std::to_string(a.pose.position.z()) + ") tag (" +
                              std::to_string(t.pose.position.x()) + ", " + std::to_string(t.pose.position.y()) +
                              ", " + std::to_string(t.pose.position.z()) + ")";
    EXPECT_EQ(want.size(), got.size()) << where;
    if (want.size() != got.size()) continue;
    std::complex<double> h_want{0.0, 0.0}, h_got{0.0, 0.0};
    for (size_t k = 0; k < want.size(); ++k) {
      EXPECT_EQ(want[k].kind, got[k].kind) << where << " path " << k;
      EXPECT_EQ(want[k].material, got[k].material) << where << " path " << k;
      EXPECT_LE((want[k].point - got[k].point).norm(), 1e-12) << where << " path " << k;
      EXPECT_LE(std::abs(want[k].length_m - got[k].length_m), 1e-12 * want[k].length_m) << where << " path " << k;
      EXPECT_LE(std::abs(want[k].contribution - got[k].contribution), 1e-12 * std::abs(want[k].contribution))
          << where << " path " << k;
      h_want += want[k].contribution;
      h_got += got[k].contribution;
      reflections += !cull && want[k].kind == PathKind::kReflection;
    }
    EXPECT_LE(std::abs(h_want - h_got), 1e-12 * std::abs(h_want)) << where;
  }
  return reflections;
}

std::shared_ptr<const Scene> scene_of(std::vector<TriangleMesh> meshes, const SceneOptions& o = {}) {
  return std::make_shared<const Scene>(std::move(meshes), MaterialAssignment{}, o);
}

// Random links inside [lo, hi] (endpoints anywhere: aisles, inside racks, between shelves).
std::vector<Link> random_links(std::mt19937_64& rng, const Vec3& lo, const Vec3& hi, int n) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto point = [&] { return Vec3(lo.x() + u(rng) * (hi.x() - lo.x()), lo.y() + u(rng) * (hi.y() - lo.y()),
                                 lo.z() + u(rng) * (hi.z() - lo.z())); };
  std::vector<Link> out;
  for (int i = 0; i < n; ++i) out.push_back({point(), point()});
  return out;
}

std::pair<Vec3, Vec3> bounds_of(const std::vector<TriangleMesh>& meshes) {
  Vec3 lo = Vec3::Constant(1e30), hi = Vec3::Constant(-1e30);
  for (const TriangleMesh& m : meshes) {
    const auto [l, h] = m.bounds();
    lo = lo.cwiseMin(l);
    hi = hi.cwiseMax(h);
  }
  return {lo, hi};
}

TEST(ExactSearch, RandomParametricWarehouses) {
  std::mt19937_64 rng(13);
  size_t reflections = 0;
  for (int k = 0; k < 4; ++k) {
    std::uniform_int_distribution<int> rows(1, 3), racks(2, 4), shelves(2, 4), tess(1, 2);
    std::uniform_real_distribution<double> len(1.5, 3.0), depth(0.6, 1.2), spacing(0.6, 1.2), aisle(1.5, 3.5);
    WarehouseParams p;
    p.rows = rows(rng), p.racks_per_row = racks(rng), p.shelves = shelves(rng), p.tessellation = tess(rng);
    p.rack_length_m = len(rng), p.rack_depth_m = depth(rng), p.shelf_spacing_m = spacing(rng), p.aisle_m = aisle(rng);
    const auto meshes = generate_warehouse(p);
    auto [lo, hi] = bounds_of(meshes);
    const auto scene = scene_of(meshes);
    // Inside the walls, up to just under the top.
    lo += Vec3(0.05, 0.05, 0.05);
    hi -= Vec3(0.05, 0.05, 0.05);
    reflections += expect_exact(scene, random_links(rng, lo, hi, 60), "warehouse " + std::to_string(k));
    reflections += expect_exact(scene, random_links(rng, lo, hi, 30), "warehouse " + std::to_string(k) + " 40 dB", 40.0);
  }
  EXPECT_GT(reflections, 500u);
}

TEST(ExactSearch, TagsOnShelfSurfacesWithCulling) {
  // Tags mounted exactly on shelf-plate surfaces (top faces, aisle-side front faces, plate corners) and
  // antennas in the aisles, at shelf height too: legs end on the covered rectangles' own planes, next to
  // their edges, and run along them. The culled search must still give the exhaustive paths, and cull.
  WarehouseParams p;
  p.rows = 3, p.racks_per_row = 3, p.shelves = 3, p.tessellation = 2;
  const auto meshes = generate_warehouse(p);
  const auto scene = scene_of(meshes);
  const double gap = 0.1;
  std::mt19937_64 rng(21);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Link> links;
  for (int i = 0; i < 150; ++i) {
    const int row = static_cast<int>(u(rng) * p.rows), rack = static_cast<int>(u(rng) * p.racks_per_row);
    const int shelf = static_cast<int>(u(rng) * p.shelves);
    const double front = row * (p.rack_depth_m + p.aisle_m) + p.aisle_m, y0 = rack * (p.rack_length_m + gap);
    const double top = 0.15 + shelf * p.shelf_spacing_m;
    Vec3 tag;
    switch (i % 3) {
      case 0: tag = {front + u(rng) * p.rack_depth_m, y0 + u(rng) * p.rack_length_m, top}; break;          // on a top
      case 1: tag = {front, y0 + u(rng) * p.rack_length_m, top - u(rng) * 0.03}; break;   // on a front
      default: tag = {front, y0 + (i % 2) * p.rack_length_m, top}; break;                               // a corner
    }
    const int aisle = static_cast<int>(u(rng) * (p.rows + 1));
    const double ax = aisle * (p.rack_depth_m + p.aisle_m) + (0.2 + 0.6 * u(rng)) * p.aisle_m;
    const double az = i % 4 == 0 ? top + 0.01 : 0.3 + 3.0 * u(rng);
    links.push_back({Vec3(ax, -1.0 + u(rng) * (p.racks_per_row * (p.rack_length_m + gap) + 2.0), az), tag});
  }
  const uint64_t culled_before = g_culled;
  EXPECT_GT(expect_exact(scene, links, "tags on shelves"), 50u);
  EXPECT_GT(g_culled - culled_before, 100u) << "the covered rectangles culled (almost) nothing";
}

TEST(ExactSearch, BlocksOfNearbyTagsShareTheGroupSearch) {
  // one_way searches the plane groups once per block of nearby tags (PathFinder::exact_groups_near) and
  // skips, for the block's links, the groups it proves useless for every tag of the block. Tags in clusters
  // (1 cm, 30 cm and 3 m across, some exactly on shelf tops and fronts or 1e-7 m off them, where a link's
  // window is at its widest and a plane is within rounding of an endpoint), antennas in aisles, at shelf
  // height and inside racks: every link's h must be the exhaustive search's (|Δh| ≤ 1e-12 |h|) and bitwise
  // the per-link search's (every path kept: a missing weak reflection would show).
  std::mt19937_64 rng(31);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  size_t links = 0, reflecting = 0;
  for (int k = 0; k < 3; ++k) {
    WarehouseParams p;
    p.rows = 2 + k % 2, p.racks_per_row = 3, p.shelves = 3, p.tessellation = 1 + k % 2;
    const auto meshes = generate_warehouse(p);
    auto [lo, hi] = bounds_of(meshes);
    lo += Vec3(0.05, 0.05, 0.05);
    hi -= Vec3(0.05, 0.05, 0.05);
    const auto scene = scene_of(meshes);
    TraceOptions ref_o;
    ref_o.candidates = CandidateMode::kExhaustive;
    ref_o.drop_below_db = 400.0;
    TraceOptions fast_o = ref_o;
    fast_o.candidates = CandidateMode::kExact;
    const RaytracedChannel reference(scene, ref_o), fast(scene, fast_o);
    const double gap = 0.1;
    std::vector<Endpoint> tags;
    for (double size : {0.01, 0.3, 3.0})
      for (int cluster = 0; cluster < 3; ++cluster) {
        Vec3 centre(lo.x() + u(rng) * (hi.x() - lo.x()), lo.y() + u(rng) * (hi.y() - lo.y()), lo.z() + u(rng) * (hi.z() - lo.z()));
        for (int j = 0; j < 20; ++j) {
          Vec3 t = centre + size * Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
          if (j % 4 == 0) {  // on a shelf top (z exactly), or 1e-7 m above or below it
            const int shelf = static_cast<int>(u(rng) * p.shelves);
            t.z() = 0.15 + shelf * p.shelf_spacing_m + (j % 8 == 0 ? 0.0 : (j % 3 == 0 ? 1e-7 : -1e-7));
          } else if (j % 4 == 1) {  // on a rack front (x exactly)
            const int row = static_cast<int>(u(rng) * p.rows);
            t.x() = row * (p.rack_depth_m + p.aisle_m) + p.aisle_m;
          }
          t = t.cwiseMax(lo).cwiseMin(hi);
          tags.push_back(endpoint(t));
        }
      }
    for (int i = 0; i < 6; ++i) {
      const int aisle = static_cast<int>(u(rng) * (p.rows + 1));
      const double ax = i == 5 ? lo.x() + u(rng) * (hi.x() - lo.x())  // anywhere, inside racks too
                               : aisle * (p.rack_depth_m + p.aisle_m) + (0.2 + 0.6 * u(rng)) * p.aisle_m;
      const double az = i % 3 == 0 ? 0.15 + p.shelf_spacing_m : 0.3 + 2.5 * u(rng);  // at a shelf top's height
      const Endpoint a = endpoint(Vec3(ax, -0.5 + u(rng) * (p.racks_per_row * (p.rack_length_m + gap) + 1.0), az), i % 2 == 1);
      std::vector<std::complex<double>> h(tags.size());
      fast.one_way(a, tags, kF, h);
      for (size_t j = 0; j < tags.size(); ++j) {
        std::complex<double> want{0.0, 0.0}, per_link{0.0, 0.0};
        size_t reflections = 0;
        for (const Path& path : reference.paths(a, tags[j], kF)) {
          want += path.contribution;
          reflections += path.kind == PathKind::kReflection;
        }
        for (const Path& path : fast.paths(a, tags[j], kF)) per_link += path.contribution;
        EXPECT_LE(std::abs(h[j] - want), 1e-12 * std::abs(want)) << "warehouse " << k << " antenna " << i << " tag " << j;
        EXPECT_EQ(h[j], per_link) << "warehouse " << k << " antenna " << i << " tag " << j;
        ++links;
        reflecting += reflections > 0;
      }
    }
  }
  EXPECT_EQ(links, 3u * 6u * 180u);
  EXPECT_GT(reflecting, links / 2);
}

TEST(ExactSearch, CullingRemovesRaysNotPaths) {
  // On a warehouse the culled search traces fewer Embree rays for the same channel, and counts what it culled;
  // off, it culls nothing (so this fails if the culling is switched off or stops culling).
  WarehouseParams p;
  p.rows = 3, p.racks_per_row = 4, p.shelves = 4, p.tessellation = 1;
  const auto scene = scene_of(generate_warehouse(p));
  TraceOptions off;
  TraceOptions on = off;
  on.cull_covered = true;
  const RaytracedChannel fast(scene, off), culled(scene, on);
  ASSERT_EQ(fast.finder().covered_rects(), nullptr);
  ASSERT_NE(culled.finder().covered_rects(), nullptr);
  EXPECT_GT(culled.finder().covered_rects()->rect_count(), 0u);
  std::mt19937_64 rng(8);
  auto [lo, hi] = bounds_of(generate_warehouse(p));
  const std::vector<Link> links = random_links(rng, lo + Vec3(0.05, 0.05, 0.05), hi - Vec3(0.05, 0.05, 0.05), 200);
  uint64_t rays[2] = {0, 0}, culls[2] = {0, 0};
  for (int mode = 0; mode < 2; ++mode)
    for (const Link& l : links) {
      const uint64_t r0 = tl_rays_traced, c0 = tl_segments_culled;
      const std::vector<Path> got = (mode ? culled : fast).paths(endpoint(l.antenna), endpoint(l.tag), kF);
      rays[mode] += tl_rays_traced - r0;
      culls[mode] += tl_segments_culled - c0;
    }
  EXPECT_EQ(culls[0], 0u);
  EXPECT_GT(culls[1], 200u);
  EXPECT_LE(rays[1] + culls[1], rays[0]) << "each culled candidate saves at least one ray";
  EXPECT_LT(rays[1], rays[0]);
}

TEST(ExactSearch, MirrorPointsAndReflectionsAreCounted) {
  // tl_mirror_points counts the image points on a facet (each needs a visibility decision) and
  // tl_reflections_found those with both legs clear. With nothing dropped, the second is the number of
  // reflection paths; without culling each mirror point costs at least one ray and each reflection two, so
  // rays ≥ links (direct paths) + points + reflections; with culling the points are the same (culling decides
  // visibility, not where mirror points are). Fails if either counter over- or under-counts.
  WarehouseParams p;
  p.rows = 3, p.racks_per_row = 4, p.shelves = 4, p.tessellation = 1;
  const auto scene = scene_of(generate_warehouse(p));
  TraceOptions off;
  off.drop_below_db = 400.0;
  TraceOptions on = off;
  on.cull_covered = true;
  const RaytracedChannel fast(scene, off), culled(scene, on);
  std::mt19937_64 rng(12);
  auto [lo, hi] = bounds_of(generate_warehouse(p));
  const std::vector<Link> links = random_links(rng, lo + Vec3(0.05, 0.05, 0.05), hi - Vec3(0.05, 0.05, 0.05), 200);
  uint64_t points[2] = {0, 0}, found[2] = {0, 0}, rays[2] = {0, 0}, paths = 0;
  for (int mode = 0; mode < 2; ++mode)
    for (const Link& l : links) {
      const uint64_t p0 = tl_mirror_points, f0 = tl_reflections_found, r0 = tl_rays_traced;
      const std::vector<Path> got = (mode ? culled : fast).paths(endpoint(l.antenna), endpoint(l.tag), kF);
      points[mode] += tl_mirror_points - p0;
      found[mode] += tl_reflections_found - f0;
      rays[mode] += tl_rays_traced - r0;
      if (mode == 0)
        paths += std::count_if(got.begin(), got.end(), [](const Path& q) { return q.kind == PathKind::kReflection; });
    }
  EXPECT_GT(found[0], 50u);
  EXPECT_EQ(found[0], paths);
  EXPECT_GT(points[0], found[0]) << "some mirror points are hidden in a warehouse";
  EXPECT_GE(rays[0], links.size() + points[0] + found[0]);
  EXPECT_EQ(points[1], points[0]);
  EXPECT_EQ(found[1], found[0]);
}

TEST(ExactSearch, NoisyMeshMergedIntoFittedPlanes) {
  // A small warehouse whose every vertex is moved by up to ±0.5 mm; facets merged with a 5 mm tolerance, so
  // each facet reflects in its own fitted plane and its triangles stand off it by up to its flatness.
  WarehouseParams p;
  p.rows = 2, p.racks_per_row = 2, p.shelves = 3, p.tessellation = 2;
  auto meshes = generate_warehouse(p);
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> noise(-0.5e-3, 0.5e-3);
  for (TriangleMesh& m : meshes)
    for (Vec3& v : m.vertices) v += Vec3(noise(rng), noise(rng), noise(rng));
  SceneOptions so;
  so.facets.distance_tolerance_m = 5e-3;
  so.facets.angle_tolerance_rad = 5e-3;
  auto [lo, hi] = bounds_of(meshes);
  const auto scene = scene_of(meshes, so);
  lo += Vec3(0.05, 0.05, 0.05);
  hi -= Vec3(0.05, 0.05, 0.05);
  EXPECT_GT(expect_exact(scene, random_links(rng, lo, hi, 120), "noisy"), 100u);
}

TEST(ExactSearch, GrazingIncidence) {
  // A 200 × 200 m tessellated metal ground; endpoints a few tenths of a millimetre to a few centimetres above
  // it and tens of metres apart: incidence within ~1e-5 rad of grazing.
  TriangleMesh ground;
  ground.name = "ground";
  ground.material_names = {"metal"};
  add_quad(ground, Vec3(-100, -100, 0), Vec3(200, 0, 0), Vec3(0, 200, 0), 0, 7, 7);
  const auto scene = scene_of({ground});
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> xy(-90.0, 90.0), h(3e-4, 3e-2);
  std::vector<Link> links;
  for (int i = 0; i < 200; ++i) links.push_back({Vec3(xy(rng), xy(rng), h(rng)), Vec3(xy(rng), xy(rng), h(rng))});
  EXPECT_GE(expect_exact(scene, links, "grazing"), 150u);
}

TEST(ExactSearch, ReflectionPointsOnEdgesAndVertices) {
  // Ground z = 0 over [0, 4]² split 4 × 4 (inner edges and vertices on integer metres and on the diagonals of
  // each quad); beside it at x ∈ [4, 6] a coplanar ground of another material (a separate facet sharing the
  // edge x = 4); a concrete wall x = 6 standing on the ground's far edge; a metal box whose bottom face rests
  // at the corner (0, 0). Antenna and tag at one height, so P is the midpoint of their ground projections:
  // dyadic coordinates put P exactly on those edges and vertices.
  TriangleMesh ground;
  ground.name = "ground";
  ground.material_names = {"metal"};
  add_quad(ground, Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0), 0, 4, 4);
  TriangleMesh other;
  other.name = "other";
  other.material_names = {"concrete"};
  add_quad(other, Vec3(4, 0, 0), Vec3(2, 0, 0), Vec3(0, 4, 0), 0, 2, 2);
  TriangleMesh wall;
  wall.name = "wall";
  wall.material_names = {"concrete"};
  add_quad(wall, Vec3(6, 0, 0), Vec3(0, 4, 0), Vec3(0, 0, 3), 0, 2, 2);
  TriangleMesh box;
  box.name = "box";
  box.material_names = {"metal"};
  add_box(box, Vec3(-1, -1, 0), Vec3(0, 0, 1), 0);
  const auto scene = scene_of({ground, other, wall, box});
  // Reflection points on the ground: inner vertices, inner edges (axis and diagonal), the outer boundary
  // and its corners, the edge shared with the other material, the wall's foot, the box's corner.
  std::vector<Vec3> points;
  for (double x : {0.0, 0.5, 1.0, 2.0, 3.5, 4.0, 5.0, 6.0})
    for (double y : {0.0, 0.25, 1.0, 2.0, 2.5, 4.0}) points.emplace_back(x, y, 0.0);
  std::vector<Link> links;
  for (const Vec3& p : points)
    for (const Vec3& d : {Vec3(1.0, 0.0, 0.0), Vec3(0.0, 1.0, 0.0), Vec3(0.5, 0.5, 0.0), Vec3(0.75, -0.25, 0.0)})
      for (double h : {0.5, 1.25}) {
        links.push_back({p - d + Vec3(0, 0, h), p + d + Vec3(0, 0, h)});
        links.push_back({p + d + Vec3(0, 0, h), p - d + Vec3(0, 0, h)});
      }
  // The wall reflects too: P exactly on its inner edges and its edge on the ground (y, z on its grid lines).
  for (double y : {0.0, 1.0, 2.0, 4.0})
    for (double z : {0.0, 1.5, 3.0})
      links.push_back({Vec3(5.0, y - 0.5, z + 0.5), Vec3(5.0, y + 0.5, z - 0.5)});
  EXPECT_GT(expect_exact(scene, links, "edges and vertices"), 200u);
}

TEST(ExactSearch, ReflectionPointsJustOffAFacet) {
  // P within ±2 µm of a tessellated facet's outer edges and corners (nothing beyond them), where the search's
  // early exits (the bounds test, the covered-rectangle shortcut before point-in-triangle) must decide as the
  // exhaustive point-in-triangle test does: a reflection up to its 1e-9 m tolerance outside, none beyond.
  TriangleMesh ground;
  ground.name = "ground";
  ground.material_names = {"metal"};
  add_quad(ground, Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 4, 0), 0, 4, 4);
  const auto scene = scene_of({ground});
  std::vector<Link> links;
  for (double off : {-2e-6, -5e-7, -5e-8, -1e-9, 0.0, 1e-10, 5e-9, 5e-8, 5e-7, 2e-6})
    for (const Vec3& p : {Vec3(1.3, 4.0 + off, 0.0), Vec3(-off, 2.6, 0.0), Vec3(4.0 + off, 4.0 + off, 0.0), Vec3(-off, -off, 0.0)})
      for (const Vec3& d : {Vec3(1.0, 0.0, 0.0), Vec3(0.6, 0.8, 0.0)}) links.push_back({p - d + Vec3(0, 0, 0.7), p + d + Vec3(0, 0, 0.7)});
  const size_t reflections = expect_exact(scene, links, "just off a facet");
  EXPECT_GT(reflections, 30u);
  EXPECT_LT(reflections, links.size());  // the points well outside reflect nowhere
}

TEST(ExactSearch, MovingObstacle) {
  // A metal crate moves across a link above a concrete floor beside a metal wall; the scene is rebuilt at each
  // position (a moving obstacle as `simulate` would see it tick by tick), the crate shadowing in turn the
  // direct path, the floor reflection's legs and the wall reflection's legs.
  TriangleMesh floor;
  floor.name = "floor";
  floor.material_names = {"concrete"};
  add_quad(floor, Vec3(-5, -5, 0), Vec3(10, 0, 0), Vec3(0, 10, 0), 0, 3, 3);
  TriangleMesh wall;
  wall.name = "wall";
  wall.material_names = {"metal"};
  add_quad(wall, Vec3(-5, 3, 0), Vec3(10, 0, 0), Vec3(0, 0, 3), 0, 2, 2);
  size_t reflections = 0;
  std::vector<Link> links;
  for (double y : {-1.0, 0.0, 1.5})
    for (double z : {0.4, 1.2}) links.push_back({Vec3(-3.0, y, z), Vec3(3.0, -y, 1.6 - z)});
  for (int k = 0; k <= 40; ++k) {
    const double x = -3.5 + 7.0 * k / 40.0;
    TriangleMesh crate;
    crate.name = "crate";
    crate.material_names = {"metal"};
    add_box(crate, Vec3(x - 0.3, -1.2 + 0.1 * (k % 7), 0.0), Vec3(x + 0.3, 0.3 + 0.1 * (k % 7), 0.9 + 0.02 * k), 0);
    reflections += expect_exact(scene_of({floor, wall, crate}), links, "crate at x = " + std::to_string(x));
  }
  EXPECT_GT(reflections, 200u);
}

// The search is named for what it is: "exact" (the default); "fast", its former name, still reads as exact so
// older scenarios and commands keep working; anything else is an error naming the field.
TEST(CandidateMode, ExactIsTheDefaultAndFastIsItsAlias) {
  EXPECT_EQ(TraceOptions{}.candidates, CandidateMode::kExact);
  EXPECT_STREQ(to_string(CandidateMode::kExact), "exact");
  EXPECT_STREQ(to_string(CandidateMode::kExhaustive), "exhaustive");
  EXPECT_EQ(parse_candidate_mode("exact", "f"), CandidateMode::kExact);
  EXPECT_EQ(parse_candidate_mode("fast", "f"), CandidateMode::kExact);
  EXPECT_EQ(parse_candidate_mode("exhaustive", "f"), CandidateMode::kExhaustive);
  try {
    parse_candidate_mode("quick", "channel_options.candidates");
    ADD_FAILURE() << "no error for 'quick'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("field 'channel_options.candidates': unknown candidate mode 'quick'"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace rfidray
