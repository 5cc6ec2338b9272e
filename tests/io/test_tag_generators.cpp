// Tags by the thousand (io/tag_generators.h, scenario key tag_sets): grids, surface tags on the paper
// warehouse's rack fronts, names, orientation from the normal, and the located errors.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/error.h"
#include "io/scenario_yaml.h"
#include "io/tag_generators.h"
#include "tests/support/input_error.h"

namespace rfidray::io {
namespace {

const std::string kDir = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/";

std::string head() {
  return "antennas:\n  - {name: a, position: [0, 0, 1]}\nscene:\n  meshes:\n    - {file: " + kDir +
         "paper_warehouse.obj}\n";
}

std::string error_of(const std::string& text) {
  return testing::input_error_of([&] { parse_scenario(text, "s.yaml"); });
}

TEST(TagGenerators, GridPointsNamesAndOrder) {
  const Scenario s = parse_scenario(head() +
                                        "tags:\n  - {name: listed, position: [9, 9, 1]}\n"
                                        "tag_sets:\n  - name: g{ix}_{iy}_{iz}\n    yaw_deg: 90\n    gain_dbi: 0\n"
                                        "    grid: {min: [0, 0, 1], max: [0.3, 0.1, 1.2], step_m: 0.1}\n",
                                    "s.yaml");
  // 4 × 2 × 3 grid points (the 0.3 end is kept despite 0.1 rounding), after the listed tag.
  ASSERT_EQ(s.tags.size(), 1u + 24u);
  EXPECT_EQ(s.tags[0].tag.name, "listed");
  EXPECT_EQ(s.tags[1].tag.name, "g0_0_0");
  EXPECT_EQ(s.tags[2].tag.name, "g1_0_0");
  EXPECT_EQ(s.tags[5].tag.name, "g0_1_0");
  EXPECT_EQ(s.tags[24].tag.name, "g3_1_2");
  EXPECT_NEAR(s.tags[24].motion.pose.position.x(), 0.3, 1e-12);
  EXPECT_NEAR(s.tags[24].motion.pose.position.z(), 1.2, 1e-12);
  EXPECT_NEAR((s.tags[3].motion.pose.orientation * Vec3::UnitX() - Vec3::UnitY()).norm(), 0.0, 1e-12);
  EXPECT_EQ(s.tags[3].tag.pattern.peak_gain_dbi, 0.0);
  // A pattern without {i} gets _{i}.
  EXPECT_EQ(tag_name("shelf", 7), "shelf_7");
}

// The east rack row of the paper warehouse: shelf fronts at x = 2.95 facing −X, posts 1 cm proud of them
// and the back posts' −X faces at x = 3.88 (raytrace/warehouse.cpp). Tags 5 cm in front of every metal surface
// of rack_east_* that faces −X lie at x = 2.90 (shelves), 2.89 (front posts) or 3.83 and face −X, local Z up.
TEST(TagGenerators, SurfaceTagsOnRackFronts) {
  const Scenario s = parse_scenario(head() +
                                        "tag_sets:\n  - name: east_{i}\n    surface: {material: metal, mesh: "
                                        "'rack_east_*', facing: [-1, 0, 0], offset_m: 0.05, step_m: 0.25}\n",
                                    "s.yaml");
  ASSERT_GT(s.tags.size(), 20u);
  std::set<std::string> names;
  size_t shelves = 0;
  for (const TagSpec& t : s.tags) {
    const Vec3& p = t.motion.pose.position;
    // The scene's planes are float (Scene): x = 2.94, 2.95, 3.88 to half a float ulp in [2, 4), 1.2e-7 m.
    constexpr double kFloat = 1.2e-7;
    EXPECT_TRUE(std::abs(p.x() - 2.90) < kFloat || std::abs(p.x() - 2.89) < kFloat || std::abs(p.x() - 3.83) < kFloat)
        << t.tag.name << " x " << p.x();
    shelves += std::abs(p.x() - 2.90) < kFloat;
    EXPECT_GE(p.y(), -9.5 - 1e-9);
    EXPECT_LE(p.y(), 1.0 + 1e-9);
    EXPECT_NEAR((t.motion.pose.orientation * Vec3::UnitX() - Vec3(-1, 0, 0)).norm(), 0.0, 1e-9);
    EXPECT_NEAR((t.motion.pose.orientation * Vec3::UnitZ() - Vec3::UnitZ()).norm(), 0.0, 1e-9);
    names.insert(t.tag.name);
  }
  EXPECT_EQ(names.size(), s.tags.size());
  // Every shelf's 3 cm front edge gets a row: 4 shelves × ~10.5 m of the five racks / 0.25 m.
  EXPECT_GT(shelves, 4u * 38u);
  // `within` keeps the tags inside a box: here the front faces only.
  const Scenario front = parse_scenario(head() +
                                            "tag_sets:\n  - surface: {mesh: 'rack_east_*', facing: [-1, 0, 0], step_m: "
                                            "0.25, within: {min: [2.5, -20, 0], max: [3, 20, 5]}}\n",
                                        "s.yaml");
  for (const TagSpec& t : front.tags) EXPECT_LT(t.motion.pose.position.x(), 3.0);
  EXPECT_LT(front.tags.size(), s.tags.size());
  // No west rack, nothing from the concrete walls.
  EXPECT_NE(error_of(head() + "tag_sets:\n  - surface: {mesh: 'nothing_*'}\n"), "");
  EXPECT_NE(error_of(head() + "tag_sets:\n  - surface: {mesh: 'nothing_*'}\n").find("selects no surface"),
            std::string::npos);
}

TEST(TagGenerators, BadSetsAreLocatedErrors) {
  const std::string h = head();
  EXPECT_NE(error_of(h + "tag_sets:\n  - name: x\n").find("needs one of 'grid'"), std::string::npos);
  EXPECT_NE(error_of(h + "tag_sets:\n  - grid: {min: [0,0,0], max: [1,1,1], step_m: 0}\n").find("step_m"),
            std::string::npos);
  EXPECT_NE(error_of(h + "tag_sets:\n  - grid: {min: [0,0,0], max: [1000,1000,100], step_m: 0.01}\n")
                .find("more than"),
            std::string::npos);
  EXPECT_NE(error_of(h + "tag_sets:\n  - grid: {min: [1,0,0], max: [0,1,1], step_m: 0.5}\n").find("must be"),
            std::string::npos);
  EXPECT_NE(error_of(h + "tag_sets:\n  - grid: {min: [0,0,0], max: [1,1,1], step_m: 0.5, stpe: 1}\n")
                .find("unknown key"),
            std::string::npos);
  const std::string dup = error_of(h + "tags:\n  - {name: t_0, position: [1, 1, 1]}\n"
                                       "tag_sets:\n  - name: t_{i}\n    grid: {min: [0,0,0], max: [1,0,0], step_m: 1}\n");
  EXPECT_NE(dup.find("already exists"), std::string::npos) << dup;
  EXPECT_NE(dup.find("s.yaml:"), std::string::npos) << dup;
}

}  // namespace
}  // namespace rfidray::io
