// Scene loading: OBJ parsing and its errors, material mapping, facet merging, the Embree scene.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>

#include "core/error.h"
#include "raytrace/obj_loader.h"
#include "raytrace/scene.h"
#include "raytrace/warehouse.h"
#include "tests/support/input_error.h"
#include "tests/support/scratch_dir.h"

namespace rfidray {
namespace {

namespace fs = std::filesystem;
constexpr double kHalfTurn = 3.14159265358979323846;

fs::path temp_file(const std::string& name, const std::string& text) {
  static const testing::ScratchDir dir("test_scene");
  return dir.write(name, text);
}

std::string error_of(const fs::path& p) {
  return testing::input_error_of([&] { load_obj(p); });
}

TEST(ObjLoader, ReadsObjectsMaterialsAndPolygons) {
  const fs::path p = temp_file("two.obj",
                               "o floor\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl concrete\nf 1 2 3 4\n"
                               "o plate\nv 0 0 1\nv 1 0 1\nv 1 1 1\nusemtl metal\nf -3 -2 -1\nusemtl wood\nf 5/1 6/1 7/1\n"
                               "vt 0 0\n");
  // vt after use is an error (index out of range at that line) — write it correctly instead:
  const fs::path q = temp_file("two_ok.obj",
                               "o floor\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl concrete\nf 1 2 3 4\n"
                               "o plate\nv 0 0 1\nv 1 0 1\nv 1 1 1\nvt 0 0\nusemtl metal\nf -3 -2 -1\nusemtl wood\nf 5/1 6/1 7/1\n");
  EXPECT_NE(error_of(p).find("two.obj:15"), std::string::npos) << error_of(p);
  const ObjScene s = load_obj(q);
  ASSERT_EQ(s.meshes.size(), 2u);
  EXPECT_EQ(s.meshes[0].name, "floor");
  EXPECT_EQ(s.meshes[0].triangle_count(), 2u);  // quad fan-triangulated
  EXPECT_EQ(s.meshes[0].material_names, std::vector<std::string>{"concrete"});
  EXPECT_EQ(s.meshes[1].name, "plate");
  ASSERT_EQ(s.meshes[1].triangle_count(), 2u);
  EXPECT_EQ(s.meshes[1].material_names[s.meshes[1].triangle_material[0]], "metal");
  EXPECT_EQ(s.meshes[1].material_names[s.meshes[1].triangle_material[1]], "wood");
  EXPECT_DOUBLE_EQ(s.meshes[1].vertices[s.meshes[1].triangles[0][2]].z(), 1.0);
  // No .mtl file: tinyobjloader's complaints about the usemtl names are surfaced as warnings.
  EXPECT_FALSE(s.warnings.empty());
  EXPECT_NE(s.warnings[0].find("two_ok.obj"), std::string::npos);
}

TEST(ObjLoader, MalformedFilesNameFileAndLine) {
  const std::string head = "# scene\nv 0 0 0\nv 1 0 0\nv 0 1 0\n";
  struct Case {
    std::string body, line, what;
  } cases[] = {
      {"v 1 2 abc\n", ":5:", "malformed number"},
      {"f 1 2 9\n", ":5:", "out of range"},
      {"f 1 2\n", ":5:", "at least 3"},
      {"f 1 x 3\n", ":5:", "malformed face index"},
      {"f 0 1 2\n", ":5:", "malformed face index"},
      {"usemtl\n", ":5:", "usemtl"},
      {"v 1 2\n", ":5:", "needs 3"},
  };
  int i = 0;
  for (const Case& c : cases) {
    const fs::path p = temp_file("bad" + std::to_string(i++) + ".obj", head + c.body);
    const std::string msg = error_of(p);
    EXPECT_NE(msg.find(p.string() + c.line), std::string::npos) << c.body << " → " << msg;
    EXPECT_NE(msg.find(c.what), std::string::npos) << c.body << " → " << msg;
  }
  EXPECT_NE(error_of("/nonexistent/x.obj").find("/nonexistent/x.obj"), std::string::npos);
}

TEST(ObjLoader, WriteThenReadRoundTrips) {
  const auto meshes = paper_warehouse_meshes();
  const fs::path p = temp_file("wh.obj", "");
  write_obj(p, meshes);
  const ObjScene s = load_obj(p);
  EXPECT_TRUE(s.warnings.empty()) << s.warnings.front();  // the .mtl was written beside it
  ASSERT_EQ(s.meshes.size(), meshes.size());
  for (size_t m = 0; m < meshes.size(); ++m) {
    EXPECT_EQ(s.meshes[m].name, meshes[m].name);
    ASSERT_EQ(s.meshes[m].triangle_count(), meshes[m].triangle_count());
    for (size_t t = 0; t < meshes[m].triangle_count(); ++t)
      for (int k = 0; k < 3; ++k)
        EXPECT_LT((s.meshes[m].vertices[s.meshes[m].triangles[t][k]] - meshes[m].vertices[meshes[m].triangles[t][k]]).norm(), 1e-9);
  }
}

TriangleMesh one_quad(const std::string& name, const std::string& material) {
  TriangleMesh m;
  m.name = name;
  m.material_names = {material};
  add_quad(m, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 0);
  return m;
}

TEST(MaterialMap, ResolutionOrderDefaultsAndErrors) {
  const std::vector<TriangleMesh> meshes = {one_quad("floor", "Concrete"), one_quad("rack", "paint"),
                                            one_quad("shelf", "paint")};
  MaterialAssignment a;
  EXPECT_THROW(resolve_materials(meshes, a), InputError);  // 'paint' is unknown and there is no default
  try {
    resolve_materials(meshes, a);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("paint"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("rack"), std::string::npos);
  }
  a.default_material = "wood";
  ResolvedMaterials r = resolve_materials(meshes, a);
  EXPECT_EQ(r.materials[r.per_triangle[0][0]].name, "concrete");  // case-insensitive built-in
  EXPECT_EQ(r.materials[r.per_triangle[1][0]].name, "wood");
  ASSERT_EQ(r.notes.size(), 2u);  // the default is reported for each mesh it applied to
  EXPECT_NE(r.notes[0].find("default 'wood'"), std::string::npos);

  a.by_material["paint"] = "metal";
  a.by_mesh["shelf"] = "glass";
  r = resolve_materials(meshes, a);
  EXPECT_EQ(r.materials[r.per_triangle[1][1]].name, "metal");
  EXPECT_EQ(r.materials[r.per_triangle[2][0]].name, "glass");  // per-mesh beats per-material
  EXPECT_TRUE(r.notes.empty());

  a.user_materials.push_back(user_material("paint", 3.0, 0.01, 0.002));
  a.by_material.clear();
  r = resolve_materials(meshes, a);
  EXPECT_EQ(r.materials[r.per_triangle[1][0]].name, "paint");
  EXPECT_DOUBLE_EQ(r.materials[r.per_triangle[1][0]].thickness_m, 0.002);

  a.by_mesh["shelf"] = "unobtainium";
  EXPECT_THROW(resolve_materials(meshes, a), InputError);
}

TEST(Facets, MergesConnectedCoplanarTriangles) {
  TriangleMesh m;
  m.name = "m";
  m.material_names = {"concrete"};
  add_quad(m, Vec3(0, 0, 0), Vec3(4, 0, 0), Vec3(0, 3, 0), 0, 8, 5);        // 80 triangles, one plane
  add_quad(m, Vec3(10, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 0, 1, 1);       // coplanar but disconnected
  add_box(m, Vec3(0, 0, 2), Vec3(1, 1, 3), 0, 2);                           // 6 faces
  const std::vector<TriangleMesh> meshes = {m};
  MaterialAssignment a;
  const Scene scene(meshes, a);
  ASSERT_EQ(scene.facets().size(), 1u + 1u + 6u);
  EXPECT_EQ(scene.facets()[0].triangles.size(), 80u);
  EXPECT_NEAR(scene.facets()[0].normal.z(), 1.0, 1e-15);
  EXPECT_NEAR(scene.facets()[0].offset_m, 0.0, 1e-15);
  EXPECT_EQ(scene.facets()[1].triangles.size(), 2u);
  for (size_t f = 2; f < 8; ++f) EXPECT_EQ(scene.facets()[f].triangles.size(), 8u);
  // Every triangle maps to the facet that lists it.
  for (uint32_t f = 0; f < scene.facets().size(); ++f)
    for (uint32_t t : scene.facets()[f].triangles) EXPECT_EQ(scene.facet_of(t), f);
  // Materials split facets: the same plane with two materials gives two facets.
  TriangleMesh two;
  two.name = "two";
  two.material_names = {"concrete", "metal"};
  add_quad(two, Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 0);
  add_quad(two, Vec3(1, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), 1);
  const Scene s2(std::vector<TriangleMesh>{two}, a);
  EXPECT_EQ(s2.facets().size(), 2u);
}

TEST(Facets, ToleranceDecidesWhatIsCoplanar) {
  TriangleMesh m;
  m.name = "bent";
  m.material_names = {"concrete"};
  m.vertices = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(1, 1, 0.001)};  // 1 mm out of plane
  m.triangles = {{0, 1, 2}, {1, 3, 2}};
  m.triangle_material = {0, 0};
  MaterialAssignment a;
  SceneOptions tight;
  EXPECT_EQ(Scene(std::vector<TriangleMesh>{m}, a, tight).facets().size(), 2u);
  SceneOptions loose;
  loose.facets.angle_tolerance_rad = 0.01;
  loose.facets.distance_tolerance_m = 0.002;
  EXPECT_EQ(Scene(std::vector<TriangleMesh>{m}, a, loose).facets().size(), 1u);
}

TEST(EmbreeScene, HitsMapBackToTrianglesFacetsAndMaterials) {
  const Scene scene(paper_warehouse_meshes(), MaterialAssignment{});
  ASSERT_FALSE(scene.empty());
  // Straight down from above the aisle: the floor.
  RayHit h = scene.bvh().intersect(Vec3(-1, 0, 1), Vec3(0, 0, -1), 0.0, 100.0);
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 1.0, 1e-6);
  const uint32_t tri = scene.triangle_id(h.geom, h.prim);
  EXPECT_EQ(scene.meshes()[h.geom].name, "floor");
  EXPECT_EQ(scene.materials()[scene.material_of(tri)].name, "concrete");
  // Towards +x at shelf height 2.0 − 1.5 cm: the east rack's shelf plate front at x = 2.95.
  h = scene.bvh().intersect(Vec3(-1, -3.0, 1.985), Vec3(1, 0, 0), 0.0, 100.0);
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 3.95, 1e-5);
  EXPECT_EQ(scene.meshes()[h.geom].name.rfind("rack_east", 0), 0u);
  EXPECT_EQ(scene.materials()[scene.material_of(scene.triangle_id(h.geom, h.prim))].name, "metal");
  const Facet& f = scene.facets()[scene.facet_of(scene.triangle_id(h.geom, h.prim))];
  EXPECT_NEAR(std::abs(f.normal.x()), 1.0, 1e-12);
  EXPECT_EQ(std::abs(f.offset_m), double(2.95f));  // the scene's geometry is float (Scene): exactly that float
  EXPECT_TRUE(scene.bvh().occluded(Vec3(-1, -3.0, 1.985), Vec3(1, 0, 0), 0.0, 4.0));
  EXPECT_FALSE(scene.bvh().occluded(Vec3(-1, -3.0, 1.985), Vec3(1, 0, 0), 0.0, 3.9));
}

// occluded_except (Embree's context filter) against walking the hits one by one with intersect(): random segments
// through a generated warehouse, every third triangle transparent. It must see through exactly those: blocked where
// the walk meets another triangle first, clear where only transparent ones lie on the segment (such segments must
// occur, or the test would pass with a filter that ignores nothing); with nothing skipped it is occluded(), with
// everything skipped it is never blocked.
TEST(EmbreeScene, OccludedExceptLooksThroughTheSkippedTrianglesOnly) {
  WarehouseParams params;
  params.rows = 2, params.racks_per_row = 2, params.shelves = 3;
  const Scene scene(generate_warehouse(params), MaterialAssignment{});
  const EmbreeScene& bvh = scene.bvh();
  const auto every_third = [](const void* s, uint32_t geom, uint32_t prim) {
    return static_cast<const Scene*>(s)->triangle_id(geom, prim) % 3 == 0;
  };
  const auto nothing = [](const void*, uint32_t, uint32_t) { return false; };
  const auto everything = [](const void*, uint32_t, uint32_t) { return true; };
  Vec3 lo = Vec3::Constant(1e30), hi = Vec3::Constant(-1e30);
  for (const Facet& f : scene.facets()) lo = lo.cwiseMin(f.lo), hi = hi.cwiseMax(f.hi);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const auto point = [&]() -> Vec3 { return lo + Vec3(u(rng), u(rng), u(rng)).cwiseProduct(hi - lo); };
  int through_skipped_only = 0, blocked = 0;
  for (int i = 0; i < 4000; ++i) {
    const Vec3 a = point(), b = point();
    const double length = (b - a).norm();
    const Vec3 dir = (b - a) / length;
    // The walk: each transparent hit is stepped over by 1 µm (these random segments meet no two triangles closer).
    bool walk_blocked = false;
    int crossed = 0;
    for (double t = 1e-4; t < length - 1e-4;) {
      const RayHit h = bvh.intersect(a, dir, t, length - 1e-4);
      if (!h.hit) break;
      if (!every_third(&scene, h.geom, h.prim)) {
        walk_blocked = true;
        break;
      }
      ++crossed;
      t = h.t + 1e-6;
    }
    const bool filtered = bvh.occluded_except(a, dir, 1e-4, length - 1e-4, every_third, &scene);
    EXPECT_EQ(filtered, walk_blocked) << "segment " << i;
    through_skipped_only += !walk_blocked && crossed > 0;
    blocked += walk_blocked;
    EXPECT_EQ(bvh.occluded_except(a, dir, 1e-4, length - 1e-4, nothing, nullptr), bvh.occluded(a, dir, 1e-4, length - 1e-4));
    EXPECT_FALSE(bvh.occluded_except(a, dir, 1e-4, length - 1e-4, everything, nullptr));
  }
  EXPECT_GT(through_skipped_only, 50);  // 75 with this seed
  EXPECT_GT(blocked, 100);
}

// Embree shares each mesh's index array instead of copying it (raytrace/embree_scene.h). The scene built from
// meshes with no spare capacity (which Scene then pads) must hit every triangle it hit before, also after the
// Scene object is moved (the shared arrays move with it) and the caller's meshes are gone; and sharing must
// save the index copy: the same meshes without the spare element (copied) cost Embree ≥ 12 bytes per triangle
// more. Each triangle's material is the one its mesh names.
TEST(EmbreeScene, SharedIndexArraysStayValidAndSaveTheCopy) {
  std::vector<TriangleMesh> meshes = paper_warehouse_meshes();
  for (TriangleMesh& m : meshes) m.triangles.shrink_to_fit();
  const std::vector<TriangleMesh> kept = meshes;  // for the expected hits
  auto built = std::make_unique<Scene>(std::move(meshes), MaterialAssignment{});
  const Scene scene(std::move(*built));
  built.reset();
  size_t n = 0, checked = 0;
  for (size_t g = 0; g < kept.size(); ++g)
    for (size_t t = 0; t < kept[g].triangles.size(); ++t) {
      const auto& tri = kept[g].triangles[t];
      const Vec3 a = kept[g].vertices[tri[0]], b = kept[g].vertices[tri[1]], c = kept[g].vertices[tri[2]];
      const Vec3 normal = (b - a).cross(c - a);
      if (normal.norm() < 1e-9) continue;
      ++checked;
      const Vec3 dir = normal.normalized(), centroid = (a + b + c) / 3.0;
      // From 1 mm in front of the centroid back onto it: this triangle (or a coplanar twin at the same t).
      const RayHit h = scene.bvh().intersect(centroid + 1e-3 * dir, -dir, 0.0, 2e-3);
      ASSERT_TRUE(h.hit) << "mesh " << g << " triangle " << t;
      EXPECT_NEAR(h.t, 1e-3, 1e-6);
      if (h.geom == g && h.prim == t) ++n;
      // material_of goes through the mesh's own material names (no per-triangle copy): the name it was given.
      EXPECT_EQ(scene.materials()[scene.material_of(scene.triangle_id(uint32_t(g), uint32_t(t)))].name,
                kept[g].material_names[kept[g].triangle_material[t]]);
    }
  EXPECT_GT(checked, 1000u);
  EXPECT_GE(10 * n, 9 * checked);  // (all of them, with Embree 3.13: no coplanar twins in this scene)
  // The same meshes as the Scene holds them, with (shared) and without (copied) the spare elements.
  const auto scene_meshes = [&](bool spare) {
    std::vector<SceneMesh> out;
    for (const TriangleMesh& m : kept) {
      SceneMesh& s = out.emplace_back();
      for (const Vec3& v : m.vertices)
        for (int k = 0; k < 3; ++k) s.vertex_xyz.push_back(static_cast<float>(v[k]));
      s.triangles = m.triangles;
      if (spare) {
        s.vertex_xyz.reserve(s.vertex_xyz.size() + 1);
        s.triangles.reserve(s.triangles.size() + 1);
      } else {
        s.vertex_xyz.shrink_to_fit();
        s.triangles.shrink_to_fit();
      }
    }
    return out;
  };
  const std::vector<SceneMesh> padded = scene_meshes(true), unpadded = scene_meshes(false);
  size_t vertex_count = 0;
  for (const SceneMesh& m : padded) vertex_count += m.triangles.empty() ? 0 : m.vertex_count();
  const EmbreeScene shared(padded, "threads=1"), copied(unpadded, "threads=1");
  EXPECT_GE(copied.embree_bytes(), shared.embree_bytes() + 12 * shared.triangle_count() + 12 * vertex_count);
}

// A triangle's mesh comes from its facet, or for a degenerate triangle (in no facet) from a search of the
// meshes' first ids; empty meshes in between share an offset with their successor.
TEST(Scene, MeshOfEveryTriangleIncludingDegenerateOnes) {
  const auto mesh = [](const std::string& name, const std::string& material, std::vector<Vec3> v,
                       std::vector<std::array<uint32_t, 3>> t) {
    TriangleMesh m;
    m.name = name;
    m.vertices = std::move(v);
    m.triangles = std::move(t);
    m.material_names = {material};
    m.triangle_material.assign(m.triangles.size(), 0);
    return m;
  };
  const std::vector<Vec3> quad = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0), Vec3(2, 0, 0)};
  std::vector<TriangleMesh> meshes;
  meshes.push_back(mesh("a", "metal", quad, {{0, 1, 2}, {0, 1, 4}, {0, 2, 3}}));  // the middle one degenerate
  meshes.push_back(mesh("empty", "glass", {}, {}));
  meshes.push_back(mesh("b", "wood", quad, {{0, 1, 4}, {0, 1, 2}}));             // degenerate first
  meshes.push_back(mesh("c", "concrete", quad, {{0, 1, 4}}));                    // degenerate only
  const Scene scene(meshes, MaterialAssignment{});
  const std::vector<uint32_t> want_mesh = {0, 0, 0, 2, 2, 3};
  const std::vector<std::string> want_material = {"metal", "metal", "metal", "wood", "wood", "concrete"};
  ASSERT_EQ(scene.triangle_count(), want_mesh.size());
  size_t degenerate = 0;
  for (uint32_t t = 0; t < scene.triangle_count(); ++t) {
    degenerate += scene.facet_of(t) == kNoFacet;
    EXPECT_EQ(scene.mesh_of(t), want_mesh[t]) << t;
    EXPECT_EQ(scene.materials()[scene.material_of(t)].name, want_material[t]) << t;
  }
  EXPECT_EQ(degenerate, 3u);
}

// One geometry for Embree and the image method: the Scene rounds every vertex to float about its local origin
// once, Embree traces that very array (shared, not a copy), and every corner and facet bound the image method
// reads is that float, widened. Vertices no float holds (rotated by an irrational angle, shifted by 0.1 m), near
// the world origin and georeferenced (5.3e6 m: the local origin moves to the scene's centre).
TEST(Scene, EmbreeTracesTheFloatVerticesTheImageMethodReads) {
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(0.1234567, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  for (const Vec3& shift : {Vec3(0.1, 0.2, 0.3), Vec3(4.5e5 + 0.1, 5.3e6 + 0.2, 120.3)}) {
    std::vector<TriangleMesh> meshes = paper_warehouse_meshes();
    size_t not_float = 0;
    for (TriangleMesh& m : meshes)
      for (Vec3& v : m.vertices) {
        v = rot * v + shift;
        not_float += double(static_cast<float>(v.x())) != v.x();
      }
    ASSERT_GT(not_float, 1000u);  // the rounding is exercised
    const Scene scene(std::move(meshes), MaterialAssignment{});
    const Vec3 o = scene.local_origin();
    EXPECT_EQ(o.isZero(), shift.norm() < 1.0);
    size_t shared = 0;
    for (size_t g = 0; g < scene.meshes().size(); ++g) {
      const SceneMesh& m = scene.meshes()[g];
      if (m.triangles.empty()) continue;
      const RTCGeometry geom = rtcGetGeometry(scene.bvh().handle(), static_cast<unsigned>(g));
      shared += rtcGetGeometryBufferData(geom, RTC_BUFFER_TYPE_VERTEX, 0) == static_cast<const void*>(m.vertex_xyz.data());
      EXPECT_GT(m.vertex_xyz.capacity(), m.vertex_xyz.size()) << "the spare float for Embree's 16-byte loads";
    }
    EXPECT_GT(shared, 10u);
    size_t checked = 0;
    for (const Facet& f : scene.facets()) {
      Vec3 lo = Vec3::Constant(INFINITY), hi = -lo;
      for (uint32_t t : f.triangles)
        for (const Vec3& c : scene.corners(t)) {
          const Vec3 local = c - o;
          for (int k = 0; k < 3; ++k) EXPECT_EQ(double(static_cast<float>(local[k])), local[k]);
          lo = lo.cwiseMin(c), hi = hi.cwiseMax(c);
          ++checked;
        }
      EXPECT_EQ(lo, f.lo);  // bitwise: the exact search's full-rectangle shortcut compares them
      EXPECT_EQ(hi, f.hi);
      EXPECT_LE(f.flatness_m, 1e-5 * (1.0 + (f.hi - o).norm()));
    }
    EXPECT_GT(checked, 3000u);
    EXPECT_EQ(scene.bounds_lo().cwiseMin(scene.bounds_hi()), scene.bounds_lo());
  }
}

TEST(SceneSpec, PlacesScalesAndMapsMaterialsWithLocatedErrors) {
  const fs::path p = temp_file("quad.obj", "o q\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nusemtl paint\nf 1 2 3 4\n");
  SceneSpec spec;
  MeshSpec m;
  m.file = p.string();
  m.pose.position = Vec3(10, 0, 2);
  m.pose.orientation = Quat(Eigen::AngleAxisd(kHalfTurn, Vec3::UnitX()));  // upside down
  m.scale = Vec3(2, 3, 1);
  m.source_line = 12;
  spec.meshes = {m};
  spec.materials.push_back({"paint", 3.0, 0.01, 0.002, 0});
  auto scene = load_scene(spec, "s.yaml");
  ASSERT_EQ(scene->facets().size(), 1u);
  EXPECT_EQ(scene->materials()[0].name, "paint");
  const Facet& f = scene->facets()[0];
  EXPECT_NEAR(f.normal.z(), -1.0, 1e-12);
  EXPECT_NEAR(f.lo.x(), 10.0, 1e-12);
  EXPECT_NEAR(f.hi.x(), 12.0, 1e-12);
  EXPECT_NEAR(f.lo.y(), -3.0, 1e-12);
  EXPECT_NEAR(f.lo.z(), 2.0, 1e-12);
  spec.materials.clear();
  spec.material_map.push_back({"paint", "wood"});
  EXPECT_EQ(load_scene(spec, "s.yaml")->materials()[0].name, "wood");
  spec.meshes[0].material = "metal";  // per-file material beats the map
  EXPECT_EQ(load_scene(spec, "s.yaml")->materials()[0].name, "metal");
  spec.meshes[0].material = "cheese";
  try {
    load_scene(spec, "s.yaml");
    FAIL() << "unknown material accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s.yaml:12: scene.meshes[0]"), std::string::npos) << e.what();
  }
  spec.meshes[0].material.clear();
  spec.material_map.clear();
  EXPECT_THROW(load_scene(spec, "s.yaml"), InputError);  // 'paint' is not a radio material and there is no default
  spec.meshes[0].file = temp_file("broken.obj", "v 0 0\n").string();
  try {
    load_scene(spec, "s.yaml");
    FAIL() << "broken OBJ accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s.yaml:12"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("broken.obj:1"), std::string::npos) << e.what();
  }
}

TEST(Warehouse, GeneratorCountsAndKeepsTheAislesClear) {
  WarehouseParams p;
  p.rows = 3;
  p.racks_per_row = 4;
  p.shelves = 3;
  p.tessellation = 2;
  const auto meshes = generate_warehouse(p);
  size_t n = 0;
  for (const auto& m : meshes) n += m.triangle_count();
  EXPECT_EQ(n, warehouse_triangle_count(p));
  // The robot path of the paper scenario stays clear of racks.
  const Scene paper(paper_warehouse_meshes(), MaterialAssignment{});
  for (double y = -10.0; y < 8.0; y += 0.5)
    EXPECT_FALSE(paper.bvh().occluded(Vec3(-1.0, y, 0.3), Vec3(0, 1, 0), 0.0, 0.5)) << y;
  EXPECT_FALSE(paper.bvh().occluded(Vec3(-1.0, 8.0, 0.3), Vec3(1, 0, 0), 0.0, 4.0));
  p.rows = 0;
  EXPECT_THROW(generate_warehouse(p), InputError);
  // ≥ 1 M triangles reachable (counted, not built, to keep the test fast).
  WarehouseParams big;
  big.rows = 20;
  big.racks_per_row = 60;
  big.shelves = 5;
  big.tessellation = 3;
  EXPECT_GE(warehouse_triangle_count(big), 1'000'000u);
}

}  // namespace
}  // namespace rfidray
