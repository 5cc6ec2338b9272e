// `rfidray link` end to end: the JSON parses, matches the library's channel, and bad input fails cleanly.
#include <gtest/gtest.h>

#include "tests/support/run_rfidray.h"

#include <array>
#include <cmath>
#include <complex>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <string>
#include <sys/wait.h>

#include "core/reader.h"
#include "core/units.h"
#include "raytrace/raytraced_channel.h"

namespace rfidray {
namespace {

struct CliRun {
  int status;
  std::string out;
};

CliRun run(const std::string& args) {
  const rfidray::testing::CliResult r = rfidray::testing::run_rfidray(args);
  return {r.status, r.output};
}

const std::string kScene = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/paper_warehouse.obj";

TEST(LinkCli, JsonMatchesTheLibrary) {
  const CliRun r = run("link --json --scene " + kScene +
                    " --antenna=-1,-3,0.6 --tag 2.9,-2.35,2.05 --antenna-pol rhcp --pattern patch:8:70 --frequency 866e6");
  ASSERT_EQ(r.status, 0) << r.out;
  const auto first_brace = r.out.find('{');
  ASSERT_NE(first_brace, std::string::npos) << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out.substr(first_brace));

  Endpoint ant, tag;
  ant.pose.position = Vec3(-1, -3, 0.6);
  ant.polarization.kind = PolarizationKind::kCircularRight;
  ant.pattern.kind = PatternKind::kPatch;
  ant.pattern.peak_gain_dbi = 8.0;
  ant.pattern.beamwidth_deg = 70.0;
  tag.pose.position = Vec3(2.9, -2.35, 2.05);
  const auto scene = load_scene({kScene}, MaterialAssignment{});
  const RaytracedChannel channel(scene);
  const auto paths = channel.paths(ant, tag, 866e6);
  const auto& jp = j["raytraced"]["paths"];
  ASSERT_EQ(jp.size(), paths.size());
  ASSERT_GE(paths.size(), 2u);  // LoS plus at least the floor reflection
  for (size_t i = 0; i < paths.size(); ++i) {
    EXPECT_EQ(jp[i]["kind"], to_string(paths[i].kind));
    EXPECT_EQ(jp[i]["material"], paths[i].material);
    EXPECT_DOUBLE_EQ(jp[i]["length_m"].get<double>(), paths[i].length_m);
    for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(jp[i]["point"][k].get<double>(), paths[i].point[k]);
    EXPECT_DOUBLE_EQ(jp[i]["coefficient"]["re"].get<double>(), paths[i].coefficient.real());
    EXPECT_DOUBLE_EQ(jp[i]["coefficient"]["im"].get<double>(), paths[i].coefficient.imag());
  }
  const std::complex<double> h = sum_paths(paths);
  EXPECT_DOUBLE_EQ(j["raytraced"]["h"]["re"].get<double>(), h.real());
  EXPECT_DOUBLE_EQ(j["raytraced"]["h"]["im"].get<double>(), h.imag());
  EXPECT_NEAR(j["raytraced"]["phase_rad"].get<double>(), wrap_to_2pi(-std::arg(h * h)), 1e-12);
  const ReaderParams reader;
  EXPECT_NEAR(j["raytraced"]["rssi_dbm"].get<double>(),
              reader.tx_power_dbm + linear_to_db(reader.modulation_factor) + 40.0 * std::log10(std::abs(h)), 1e-9);
  // Ideal channel: free space, |h| = √G λ/(4πD) with the patch gain towards the tag.
  const double d = (tag.pose.position - ant.pose.position).norm();
  const std::complex<double> hi(j["ideal"]["h"]["re"].get<double>(), j["ideal"]["h"]["im"].get<double>());
  const double g = ant.pattern.gain_linear((tag.pose.position - ant.pose.position) / d);
  EXPECT_NEAR(std::abs(hi), std::sqrt(g) * wavelength_m(866e6) / (4 * kPi * d), 1e-15);
  EXPECT_NEAR(j["ideal"]["phase_rad"].get<double>(), wrap_to_2pi(2.0 * wavenumber_rad_m(866e6) * d), 1e-9);
  // The P.2040 extrapolation below 1 GHz is reported.
  EXPECT_NE(j["scene"]["warnings"].dump().find("extrapolated"), std::string::npos);
}

TEST(LinkCli, TableAndLevels) {
  const CliRun table = run("link --scene " + kScene + " --antenna=-1,-3,0.6 --tag 2.9,-2.35,2.05");
  ASSERT_EQ(table.status, 0) << table.out;
  EXPECT_NE(table.out.find("reflection"), std::string::npos);
  EXPECT_NE(table.out.find("RSSI"), std::string::npos);
  const CliRun los = run("link --json --channel los --scene " + kScene + " --antenna=-1,-3,0.6 --tag 2.9,-2.35,2.05");
  ASSERT_EQ(los.status, 0) << los.out;
  const auto j = nlohmann::json::parse(los.out.substr(los.out.find('{')));
  ASSERT_EQ(j["raytraced"]["paths"].size(), 1u);
  EXPECT_EQ(j["raytraced"]["paths"][0]["kind"], "los");
}

// --level is kept as an alias of --channel: the same level, and --help says it is an alias.
TEST(LinkCli, LevelIsAnAliasOfChannel) {
  const std::string where = " --scene " + kScene + " --antenna=-1,-3,0.6 --tag 2.9,-2.35,2.05";
  const CliRun level = run("link --json --level los" + where);
  const CliRun channel = run("link --json --channel los" + where);
  ASSERT_EQ(level.status, 0) << level.out;
  ASSERT_EQ(channel.status, 0) << channel.out;
  const auto jl = nlohmann::json::parse(level.out.substr(level.out.find('{')));
  const auto jc = nlohmann::json::parse(channel.out.substr(channel.out.find('{')));
  EXPECT_EQ(jl["level"], "los");
  EXPECT_EQ(jl["raytraced"], jc["raytraced"]);
  const CliRun bad = run("link --level multi" + where);
  EXPECT_EQ(bad.status, 2) << bad.out;
  EXPECT_NE(bad.out.find("--channel"), std::string::npos) << bad.out;
  const CliRun help = run("link --help");
  ASSERT_EQ(help.status, 0) << help.out;
  EXPECT_NE(help.out.find("--channel,--level"), std::string::npos) << help.out;
  EXPECT_NE(help.out.find("--level is an alias of --channel"), std::string::npos) << help.out;
}

// The default search is named exact; "fast", its former name, gives the same paths and reports itself as exact.
TEST(LinkCli, CandidatesExactByDefaultAndFastIsItsAlias) {
  const std::string where = " --json --scene " + kScene + " --antenna=-1,-3,0.6 --tag 2.9,-2.35,2.05";
  const CliRun plain = run("link" + where), fast = run("link --candidates fast" + where);
  ASSERT_EQ(plain.status, 0) << plain.out;
  ASSERT_EQ(fast.status, 0) << fast.out;
  const auto jp = nlohmann::json::parse(plain.out.substr(plain.out.find('{')));
  const auto jf = nlohmann::json::parse(fast.out.substr(fast.out.find('{')));
  EXPECT_EQ(jp["candidates"], "exact");
  EXPECT_EQ(jf["candidates"], "exact");
  EXPECT_EQ(jp["raytraced"], jf["raytraced"]);
}

TEST(LinkCli, BadInputFailsWithAMessage) {
  const std::string ok = " --antenna 0,0,1 --tag 1,0,1";
  struct Case {
    std::string args, needle;
  } cases[] = {
      {"link --scene /nonexistent.obj" + ok, "/nonexistent.obj"},
      {"link --scene " + kScene + " --antenna 0,0 --tag 1,0,1", "--antenna"},
      {"link --scene " + kScene + " --antenna 0,0,x --tag 1,0,1", "'x'"},
      {"link --scene " + kScene + ok + " --channel multi", "field '--channel': unknown channel 'multi'"},
      {"link --scene " + kScene + ok + " --material cheese", "cheese"},
      {"link --scene " + kScene + ok + " --antenna-pol linear:0,0,0", "--antenna-pol"},
      {"link --scene " + kScene + ok + " --pattern patch", "patch"},
      {"link --scene " + kScene + " --antenna 1,0,1 --tag 1,0,1", "coincide"},
  };
  for (const Case& c : cases) {
    const CliRun r = run(c.args);
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.out;
    EXPECT_NE(r.out.find(c.needle), std::string::npos) << c.args << "\n" << r.out;
    EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
  }
}

// The tag as an antenna (issue #32's command): the JSON has the tag_antenna object with the impedance and the power
// transfer of a half-wave dipole 1 cm from metal (−10.3 dB, NEC-2: tests/core/test_tag_antenna.cpp).
TEST(LinkCli, TagAntennaOnMetalPrintsItsCoupling) {
  const std::string floor = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/floor_4m.obj";
  const CliRun r = run("link --material concrete --scene " + floor + " --antenna 0,0,1 --tag 3,0,1 --tag-rpy 0,0,180 --frequency 866e6 "
                       "--tag-antenna dipole:0.166:0.0005 --tag-chip matched --tag-backing metal:0.01 --json 2>/dev/null");
  ASSERT_EQ(r.status, 0) << r.out;
  const nlohmann::json j = nlohmann::json::parse(r.out.substr(r.out.find('{')));
  const auto& t = j["tag_antenna"];
  EXPECT_NEAR(t["impedance_re_ohm"].get<double>(), 1.9, 0.2);
  EXPECT_LT(std::abs(t["impedance_im_ohm"].get<double>()), 3.5);
  EXPECT_NEAR(t["power_transfer_db"].get<double>(), -10.3, 0.3);
  EXPECT_NEAR(t["power_transfer"].get<double>(), std::pow(10.0, t["power_transfer_db"].get<double>() / 10.0), 1e-12);
  EXPECT_EQ(t["backing"]["kind"], "given");
  // The chip's power is the point tag's on the same link plus the image path and F (= τ · R_a0 / R_a).
  const CliRun point = run("link --material concrete --scene " + floor + " --antenna 0,0,1 --tag 3,0,1 --tag-rpy 0,0,180 --frequency 866e6 "
                           "--json 2>/dev/null");
  ASSERT_EQ(point.status, 0) << point.out;
  const nlohmann::json jp = nlohmann::json::parse(point.out.substr(point.out.find('{')));
  EXPECT_FALSE(jp.contains("tag_antenna"));
  const double image_db = 10.0 * std::log10(std::norm(std::complex<double>(t["image_factor"]["re"], t["image_factor"]["im"])));
  EXPECT_NEAR(j["raytraced"]["tag_power_dbm"].get<double>() - jp["raytraced"]["tag_power_dbm"].get<double>(),
              image_db + t["chip_power_factor_db"].get<double>(), 1e-6);
  // Facing away from the reader, the metal behind it blocks the link.
  const CliRun back = run("link --material concrete --scene " + floor + " --antenna 0,0,1 --tag 3,0,1 --frequency 866e6 --json "
                          "--tag-antenna dipole:0.166:0.0005 --tag-backing metal:0.01 2>/dev/null");
  ASSERT_EQ(back.status, 0) << back.out;
  EXPECT_FALSE(nlohmann::json::parse(back.out.substr(back.out.find('{')))["raytraced"]["readable"].get<bool>());
}

TEST(LinkCli, TagAntennaBadUsesExitTwoNamingTheOption) {
  const std::string floor = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/floor_4m.obj";
  const std::string base = "link --material concrete --scene " + floor + " --antenna 0,0,1 --tag 3,0,1 ";
  const CliRun chip_alone = run(base + "--tag-chip series:20:1e-12");
  EXPECT_EQ(chip_alone.status, 2);
  EXPECT_NE(chip_alone.out.find("--tag-antenna"), std::string::npos) << chip_alone.out;
  const CliRun bad = run(base + "--tag-antenna dipole:0.166");
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.out.find("--tag-antenna"), std::string::npos) << bad.out;
  const CliRun cheese = run(base + "--tag-antenna dipole:0.166:0.0005 --tag-backing cheese:0.01");
  EXPECT_EQ(cheese.status, 2);
  EXPECT_NE(cheese.out.find("--tag-backing"), std::string::npos) << cheese.out;
  EXPECT_NE(cheese.out.find("water"), std::string::npos) << "the error lists the known materials: " << cheese.out;
  const CliRun negative = run(base + "--tag-antenna dipole:0.166:0.0005 --tag-backing dielectric:-2:0:0.01");
  EXPECT_EQ(negative.status, 2);
  EXPECT_NE(negative.out.find("--tag-backing"), std::string::npos) << negative.out;
}

// A tag 1 cm from water: its impedance moves far less than 1 cm from metal (τ −0.1 dB against −10.3 dB), but water
// reflects (Γ ≈ −0.8 at normal incidence) and absorbs, so the chip still receives several dB less than in free
// space (NEC-2's plane wave over its Sommerfeld ground agrees: tests/core/test_tag_antenna.cpp). --tag-mount is the
// same option as --tag-backing.
TEST(LinkCli, TagOnWaterIsDetunedByItsReflectionMoreThanItsImpedance) {
  const std::string floor = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/floor_4m.obj";
  const std::string base = "link --material concrete --scene " + floor +
                           " --antenna 0,0,1 --tag 3,0,1 --tag-rpy 0,0,180 --frequency 866e6 --json --tag-antenna dipole:0.166:0.0005 ";
  const auto coupling = [&](const std::string& backing) {
    const CliRun r = run(base + backing + " 2>/dev/null");
    EXPECT_EQ(r.status, 0) << r.out;
    return nlohmann::json::parse(r.out.substr(r.out.find('{')));
  };
  const nlohmann::json water = coupling("--tag-mount water:0.01");
  const nlohmann::json metal = coupling("--tag-backing metal:0.01");
  EXPECT_EQ(water["tag_antenna"]["backing"]["material"], "water");
  EXPECT_FALSE(water["tag_antenna"]["backing"]["perfect_conductor"].get<bool>());
  EXPECT_NEAR(water["tag_antenna"]["backing"]["relative_permittivity"]["re"].get<double>(), 78.0, 3.0);  // Kaatze 1989
  EXPECT_GT(water["tag_antenna"]["power_transfer_db"].get<double>(), metal["tag_antenna"]["power_transfer_db"].get<double>() + 5.0);
  EXPECT_GT(water["tag_antenna"]["power_transfer_db"].get<double>(), -1.0);
  const double free_dbm = coupling("")["raytraced"]["tag_power_dbm"].get<double>();
  const double water_dbm = water["raytraced"]["tag_power_dbm"].get<double>();
  EXPECT_LT(water_dbm, free_dbm - 3.0);
  // The impedance differs from free space's (NEC-2 Sommerfeld: 53.1 + j7.9 ohm for this dipole at 1 cm).
  EXPECT_NEAR(water["tag_antenna"]["impedance_re_ohm"].get<double>(), 53.1, 53.1 * 0.1);
}

}  // namespace
}  // namespace rfidray
