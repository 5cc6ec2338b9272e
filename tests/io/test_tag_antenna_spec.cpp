// The tag antenna's text and YAML forms (io/tag_antenna_spec.h, io/scenario_yaml.cpp): what they parse to, the
// defaults (a tag with an antenna is backed by the scene), and errors that name the field, file and line.
#include <gtest/gtest.h>

#include <string>

#include "core/error.h"
#include "io/scenario_yaml.h"
#include "io/tag_antenna_spec.h"
#include "tests/support/input_error.h"
#include "tests/support/scratch_dir.h"

namespace rfidray::io {
namespace {

using testing::input_error_of;

const std::string kHead = R"(
antennas:
  - name: reader
    model: physical
    position: [0, 0, 1]
)";

TEST(TagAntennaSpec, TextFormsParse) {
  const TagAntennaSpec d = parse_tag_antenna("dipole:0.166:0.0005:3.5e7", "f");
  EXPECT_EQ(d.kind, TagAntennaSpec::Kind::kDipole);
  EXPECT_DOUBLE_EQ(d.dipole.length_m, 0.166);
  EXPECT_DOUBLE_EQ(d.dipole.radius_m, 0.0005);
  EXPECT_DOUBLE_EQ(d.dipole.conductivity_s_m, 3.5e7);
  const TagChipSpec s = parse_tag_chip("series:20:1.1e-12", "f");
  EXPECT_EQ(s.kind, TagChipSpec::Kind::kSeries);
  EXPECT_DOUBLE_EQ(s.capacitance_f, 1.1e-12);
  EXPECT_DOUBLE_EQ(parse_tag_chip("matched:915e6", "f").design_frequency_hz, 915e6);
  const TagBackingSpec m = parse_tag_backing("metal:0.01", "f");
  EXPECT_EQ(m.kind, TagBackingSpec::Kind::kGiven);
  EXPECT_EQ(m.material.name, "metal");
  EXPECT_TRUE(m.material.perfect_conductor);
  EXPECT_DOUBLE_EQ(m.distance_m, 0.01);
  const TagBackingSpec w = parse_tag_backing("water:0.005", "f");
  EXPECT_EQ(w.material.name, "water");
  EXPECT_FALSE(w.material.perfect_conductor);
  EXPECT_NEAR(w.material.relative_permittivity(866e6), 78.2, 1e-9);
  const TagBackingSpec c = parse_tag_backing("dielectric:2.0:0.005:0.003", "f");
  EXPECT_DOUBLE_EQ(c.material.relative_permittivity(866e6), 2.0);
  EXPECT_DOUBLE_EQ(c.material.conductivity_s_m(866e6), 0.005);
  EXPECT_DOUBLE_EQ(c.distance_m, 0.003);
  EXPECT_NE(input_error_of([] { parse_tag_backing("dielectric:0.5:0:0.01", "option --tag-backing"); }).find("dielectric"),
            std::string::npos);
  EXPECT_NE(input_error_of([] { parse_tag_backing("cheese:0.01", "option --tag-backing"); }).find("option --tag-backing"),
            std::string::npos);
  EXPECT_EQ(parse_tag_backing("scene", "f").kind, TagBackingSpec::Kind::kScene);
  EXPECT_EQ(parse_tag_backing("none", "f").kind, TagBackingSpec::Kind::kNone);
  EXPECT_NE(input_error_of([] { parse_tag_antenna("dipole:0.166", "option --tag-antenna"); }).find("option --tag-antenna"),
            std::string::npos);
  EXPECT_NE(input_error_of([] { parse_tag_chip("series:x:1e-12", "option --tag-chip"); }).find("resistance"),
            std::string::npos);
  EXPECT_NE(input_error_of([] { parse_tag_backing("metal", "option --tag-backing"); }).find("MATERIAL:DISTANCE_M"),
            std::string::npos);
}

TEST(TagAntennaSpec, ScenarioKeysAndTheSceneMountDefault) {
  const Scenario s = parse_scenario(kHead + R"(
tags:
  - name: plain
    position: [3, 0, 1]
  - name: on_shelf
    position: [3, 1, 1]
    antenna: {type: dipole, length_m: 0.166, radius_m: 0.0005}
  - name: on_can
    position: [3, 2, 1]
    antenna: dipole:0.15:0.0004
    chip: {type: parallel, resistance_ohm: 1500, capacitance_f: 1.0e-12}
    backing: {material: metal, distance_m: 0.003}
  - name: inlay
    position: [3, 3, 1]
    antenna: {type: table, rows: [[860e6, 20, 150], [960e6, 25, 170]]}
    backing: none
)", "s.yaml");
  ASSERT_EQ(s.tags.size(), 4u);
  EXPECT_EQ(s.tags[0].tag.antenna.kind, TagAntennaSpec::Kind::kNone);  // the paper's point tag, unchanged
  EXPECT_EQ(s.tags[0].tag.backing.kind, TagBackingSpec::Kind::kNone);
  EXPECT_EQ(s.tags[1].tag.antenna.kind, TagAntennaSpec::Kind::kDipole);
  EXPECT_EQ(s.tags[1].tag.backing.kind, TagBackingSpec::Kind::kScene);
  EXPECT_EQ(s.tags[2].tag.chip.kind, TagChipSpec::Kind::kParallel);
  EXPECT_EQ(s.tags[2].tag.backing.kind, TagBackingSpec::Kind::kGiven);
  EXPECT_DOUBLE_EQ(s.tags[2].tag.backing.distance_m, 0.003);
  ASSERT_EQ(s.tags[3].tag.antenna.table.size(), 2u);
  EXPECT_DOUBLE_EQ(s.tags[3].tag.antenna.table[1].impedance_ohm.imag(), 170.0);
  EXPECT_EQ(s.tags[3].tag.backing.kind, TagBackingSpec::Kind::kNone);
}

TEST(TagAntennaSpec, ScenarioErrorsNameTheField) {
  const auto err = [](const std::string& tag_keys) {
    return input_error_of([&] {
      parse_scenario(kHead + "tags:\n  - name: t\n    position: [3, 0, 1]\n" + tag_keys, "s.yaml");
    });
  };
  EXPECT_NE(err("    antenna: {type: loop}\n").find("tags[0].antenna.type"), std::string::npos);
  EXPECT_NE(err("    antenna: {type: dipole, length_m: 0.166}\n").find("radius_m"), std::string::npos);
  EXPECT_NE(err("    antenna: dipole:0.166:0.0005\n    backing: {material: cheese, distance_m: 0.01}\n")
                .find("backing.material"),
            std::string::npos);
  EXPECT_NE(err("    antenna: dipole:0.166:0.0005\n    backing: {material: dielectric, relative_permittivity: 0.5, "
                "conductivity_s_m: 0, distance_m: 0.01}\n")
                .find("s.yaml:"),
            std::string::npos);  // ε' < 1, located in the file
  EXPECT_NE(err("    antenna: dipole:0.166:0.0005\n    backing: {material: water, relative_permittivity: 2, distance_m: 0.01}\n")
                .find("relative_permittivity"),
            std::string::npos);  // only a dielectric takes its own ε
  EXPECT_NE(err("    chip: {type: series, resistance_ohm: 20, capacitance_f: 1e-12}\n").find("antenna"),
            std::string::npos);  // a chip without an antenna
  EXPECT_NE(err("    antenna: dipole:0.166:0.0005\n    backing: {material: metal, distance_m: 0.0001}\n").find("radius"),
            std::string::npos);
}

TEST(TagAntennaSpec, TableFileErrorsNameFileAndLine) {
  const testing::ScratchDir dir("tag_antenna_table");
  const auto good = dir.write("inlay.csv", "frequency_hz,resistance_ohm,reactance_ohm\n860e6,20,150\n960e6,25,170\n");
  EXPECT_EQ(read_tag_antenna_table(good.string()).size(), 2u);
  const auto bad = dir.write("bad.csv", "frequency_hz,resistance_ohm,reactance_ohm\n860e6,20,150\n850e6,25,170\n");
  const std::string e = input_error_of([&] { read_tag_antenna_table(bad.string()); });
  EXPECT_NE(e.find("bad.csv:3"), std::string::npos) << e;
  const auto header = dir.write("header.csv", "f,r,x\n860e6,20,150\n");
  EXPECT_NE(input_error_of([&] { read_tag_antenna_table(header.string()); }).find("header"), std::string::npos);
  EXPECT_NE(input_error_of([&] { read_tag_antenna_table((dir / "missing.csv").string()); }).find("missing.csv"),
            std::string::npos);
}

}  // namespace
}  // namespace rfidray::io
