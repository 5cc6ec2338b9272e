// Issue #12: legitimate large inputs work — a georeferenced (UTM-sized) scene traces the same paths as the same
// scene near the origin, an OBJ with tens of thousands of `o` groups loads in memory linear in its size — and
// bad ones are refused with their file:line.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "core/error.h"
#include "raytrace/obj_loader.h"
#include "raytrace/raytraced_channel.h"
#include "tests/support/endpoint_at.h"
#include "raytrace/warehouse.h"
#include "tests/support/scratch_dir.h"

namespace rfidray {
namespace {

namespace fs = std::filesystem;

std::vector<TriangleMesh> shifted(std::vector<TriangleMesh> meshes, const Vec3& by) {
  for (TriangleMesh& m : meshes)
    for (Vec3& v : m.vertices) v += by;
  return meshes;
}


TEST(LargeCoordinates, UtmSizedSceneGivesTheSamePathsAsTheSceneNearTheOrigin) {
  const Vec3 utm(512345.0, 5012345.0, 0.0);  // a UTM easting / northing, metres
  TraceOptions o;
  o.level = ChannelLevel::kSingleBounce;
  o.drop_below_db = 400.0;
  const auto near_scene = std::make_shared<const Scene>(paper_warehouse_meshes(), MaterialAssignment{});
  const auto far_scene = std::make_shared<const Scene>(shifted(paper_warehouse_meshes(), utm), MaterialAssignment{});
  ASSERT_EQ(near_scene->facets().size(), far_scene->facets().size());
  for (CandidateMode mode : {CandidateMode::kExact, CandidateMode::kExhaustive}) {
    o.candidates = mode;
    const RaytracedChannel near_ch(near_scene, o), far_ch(far_scene, o);
    const Vec3 antennas[] = {{-1.0, -3.0, 0.6}, {3.5, -4.0, 2.0}, {-1.0, 5.0, 1.68}};
    const Vec3 tags[] = {{2.9, -2.35, 2.05}, {-4.85, -7.7, 1.85}, {2.9, 0.2, 2.05}, {0.5, 7.5, 1.0}};
    size_t total = 0;
    for (const Vec3& a : antennas)
      for (const Vec3& t : tags) {
        const auto pn = near_ch.paths(testing::endpoint_at(a), testing::endpoint_at(t), 866e6);
        const auto pf = far_ch.paths(testing::endpoint_at(a + utm), testing::endpoint_at(t + utm), 866e6);
        ASSERT_EQ(pn.size(), pf.size()) << "antenna " << a.transpose() << ", tag " << t.transpose();
        total += pn.size();
        // Each scene rounds its vertices to float about its own local origin (the world origin; the UTM
        // scene's centre), ≤ 0.5 ulp at 16 m = 4.8e-7 m per coordinate, so their planes differ by up to
        // ~2e-6 m: lengths and points agree to 4e-6 m, contributions to k·4e-6 m ≈ 7e-5 relative at 866 MHz.
        // Without the recentring, float at 5e6 m is 0.5 m coarse.
        for (size_t i = 0; i < pn.size(); ++i) {
          EXPECT_EQ(pn[i].kind, pf[i].kind);
          EXPECT_NEAR(pn[i].length_m, pf[i].length_m, 4e-6);
          EXPECT_LT((pn[i].point + utm - pf[i].point).norm(), 4e-6);
          EXPECT_LT(std::abs(pn[i].contribution - pf[i].contribution), 1e-4 * std::abs(pn[i].contribution) + 1e-15);
        }
      }
    EXPECT_GT(total, 40u);  // reflections were found, not just line of sight
  }
}

TEST(LargeCoordinates, VerticesOutsideTheCoordinateRangeNameTheMesh) {
  TriangleMesh m;
  m.name = "huge";
  m.material_names = {"metal"};
  add_quad(m, Vec3(0, 0, 0), Vec3(1e300, 0, 0), Vec3(0, 1, 0), 0);
  try {
    Scene s({m}, MaterialAssignment{});
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh 'huge'"), std::string::npos) << e.what();
  }
}

class ObjFiles : public ::testing::Test {
 protected:
  const testing::ScratchDir scratch_{testing::ScratchDir::current_test_name("large")};
  const fs::path dir_ = scratch_.path();
};

TEST_F(ObjFiles, FortyThousandGroupsLoadInLinearMemory) {
  // 40 000 groups of one triangle each: a dense vertex map per group would need 40 000 × 120 000 entries
  // (~19 GB); per-group maps hold 3 entries each.
  const int groups = 40000;
  const fs::path obj = dir_ / "groups.obj";
  {
    std::ofstream out(obj);
    out << "usemtl metal\n";
    for (int g = 0; g < groups; ++g) {
      out << "o g" << g << "\nv " << g << " 0 0\nv " << g << " 1 0\nv " << g << " 0 1\n";
      out << "f -3 -2 -1\n";
    }
  }
  const ObjScene s = load_obj(obj);
  ASSERT_EQ(s.meshes.size(), size_t(groups));
  size_t vertices = 0;
  for (const TriangleMesh& m : s.meshes) vertices += m.vertices.size();
  EXPECT_EQ(vertices, size_t(3 * groups));
  EXPECT_EQ(s.meshes[123].vertices[0], Vec3(123, 0, 0));
}

TEST_F(ObjFiles, NonRegularFilesAndHugeCoordinatesAreRefusedWithTheirLine) {
  EXPECT_THROW(load_obj("/dev/zero"), InputError);
  {
    std::ofstream(dir_ / "m.obj") << "mtllib /dev/zero\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    try {
      load_obj(dir_ / "m.obj");
      FAIL() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("m.obj:1: mtllib"), std::string::npos) << e.what();
    }
  }
  {
    std::ofstream(dir_ / "h.obj") << "v 1e308 1e308 1e308\nv -1e308 -1e308 -1e308\nv 1e308 -1e308 0\nf 1 2 3\n";
    try {
      load_obj(dir_ / "h.obj");
      FAIL() << "accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("h.obj:1: vertex coordinate"), std::string::npos) << e.what();
    }
  }
  {
    std::ofstream(dir_ / "n.obj") << "v " << std::string(100000, '7') << "x 0 0\n";
    try {
      load_obj(dir_ / "n.obj");
      FAIL() << "accepted";
    } catch (const InputError& e) {
      EXPECT_LT(std::string(e.what()).size(), 300u);
      EXPECT_NE(std::string(e.what()).find("n.obj:1:"), std::string::npos);
    }
  }
}

TEST(Warehouse, SizeIsCheckedBeforeAllocatingWithTheEstimate) {
  WarehouseParams p;
  p.rows = 1073741824;
  p.racks_per_row = 1073741824;
  p.shelves = 1;
  p.tessellation = 4;
  try {
    generate_warehouse(p);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("about 9.59231e+20 triangles"), std::string::npos) << e.what();
  }
  WarehouseParams q;
  q.rack_length_m = 1e308;
  EXPECT_THROW(generate_warehouse(q), InputError);
  q = WarehouseParams{};
  q.shelf_spacing_m = std::nan("");
  EXPECT_THROW(generate_warehouse(q), InputError);
}

}  // namespace
}  // namespace rfidray
