// Scenario YAML: the paper scenario's values, parameter-name aliases, motion kinds, and located errors.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "io/antenna_file.h"
#include "io/scenario_yaml.h"
#include "core/error.h"
#include "core/simulation.h"
#include "core/units.h"
#include "tests/support/input_error.h"

namespace rfidray::io {
namespace {

const std::string kPaper = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/paper_warehouse.yaml";

// The message of the InputError that parsing `text` throws ("" if none).
std::string error_of(const std::string& text) {
  return testing::input_error_of([&] { parse_scenario(text, "s.yaml"); });
}

TEST(ScenarioYaml, PaperWarehouseHasTable1AndTheTenTags) {
  const Scenario s = load_scenario(kPaper);
  ASSERT_EQ(s.antennas.size(), 2u);
  ASSERT_EQ(s.tags.size(), 10u);
  ASSERT_EQ(s.robots.size(), 1u);
  const ReaderParams& mobile = s.antennas[0].reader;
  const ReaderParams& fixed = s.antennas[1].reader;
  for (const ReaderParams* r : {&mobile, &fixed}) {
    EXPECT_EQ(r->frequencies_hz, std::vector<double>{865.7e6});
    EXPECT_EQ(r->noise_phi_rad, 0.1);
    EXPECT_EQ(r->range_m, 7.0);
    EXPECT_EQ(r->update_rate_hz, 15.0);
    EXPECT_EQ(r->optional_distribution.kind, DistributionKind::kNone);
    EXPECT_EQ(r->model, ReaderModelKind::kPaper);
  }
  EXPECT_EQ(mobile.noise_rssi, 0.01);
  EXPECT_EQ(mobile.communication_gain, 3.0);
  EXPECT_EQ(fixed.noise_rssi, 0.008);
  EXPECT_EQ(fixed.communication_gain, 1.0);
  EXPECT_EQ(s.antennas[0].motion.kind, MotionSpec::Kind::kRobot);
  EXPECT_EQ(s.antennas[0].motion.pose.position.z(), 1.68);
  EXPECT_EQ(s.antennas[1].motion.kind, MotionSpec::Kind::kFixed);
  EXPECT_EQ(s.antennas[1].motion.pose.position, Vec3(3.5, -4.0, 2.0));
  EXPECT_EQ(s.tags[0].motion.pose.position, Vec3(2.90, 0.57, 2.05));
  EXPECT_EQ(s.tags[9].motion.pose.position, Vec3(-4.85, 5.95, 1.85));
  const std::vector<Vec3> path{Vec3(-1, -10, 0), Vec3(-1, 8, 0), Vec3(3, 8, 0)};
  EXPECT_EQ(s.robots[0].waypoints, path);
  // 0.35 m/s through eq. 7: ω_wheel = v / r.
  EXPECT_NEAR(s.robots[0].drive.drive_wheel_speed_rad_s * s.robots[0].drive.wheel_radius_m, 0.35, 1e-15);
  // The run lasts until the robot ends: 18 m + 4 m at 0.35 m/s plus a quarter turn at 0.5 rad/s.
  const SceneMotion m = build_motion(s);
  EXPECT_NEAR(scenario_duration_s(s, m), 22.0 / 0.35 + (kPi / 2) / 0.5, 1e-9);
  // At t = 0 the mobile antenna is 1.68 m above the start and faces +X (robot north, mounted yaw −90°).
  const Pose p0 = m.antennas[0]->pose_at(0.0);
  EXPECT_NEAR((p0.position - Vec3(-1, -10, 1.68)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((p0.orientation * Vec3::UnitX() - Vec3::UnitX()).norm(), 0.0, 1e-12);
}

TEST(ScenarioYaml, SeedPluginNamesEqualOurNames) {
  const Scenario seed_names = parse_scenario(R"(duration_s: 1
antennas:
  - name: a
    position: [0, 0, 1]
    frequency: 866.3e6
    noisephi: 0.2
    noiserssi: 0.03
    range: 5
    optional_distribution: normal
    optional_distribution_params: "0.0 0.1"
    communication_gain: 2
    update_rate: 10
)", "s.yaml");
  const Scenario ours = parse_scenario(R"(duration_s: 1
antennas:
  - name: a
    position: [0, 0, 1]
    frequency_hz: 866.3e6
    noise_phi_rad: 0.2
    noise_rssi: 0.03
    range_m: 5
    optional_distribution: normal
    optional_distribution_params: [0.0, 0.1]
    communication_gain: 2
    update_rate_hz: 10
)", "s.yaml");
  const ReaderParams& a = seed_names.antennas[0].reader;
  const ReaderParams& b = ours.antennas[0].reader;
  EXPECT_EQ(a.frequencies_hz, b.frequencies_hz);
  EXPECT_EQ(a.frequencies_hz[0], 866.3e6);
  EXPECT_EQ(a.noise_phi_rad, 0.2);
  EXPECT_EQ(a.noise_phi_rad, b.noise_phi_rad);
  EXPECT_EQ(a.noise_rssi, 0.03);
  EXPECT_EQ(a.noise_rssi, b.noise_rssi);
  EXPECT_EQ(a.range_m, 5.0);
  EXPECT_EQ(a.range_m, b.range_m);
  EXPECT_EQ(a.update_rate_hz, 10.0);
  EXPECT_EQ(a.update_rate_hz, b.update_rate_hz);
  EXPECT_EQ(a.optional_distribution.kind, DistributionKind::kNormal);
  EXPECT_EQ(a.optional_distribution.params, b.optional_distribution.params);
  EXPECT_EQ(a.optional_distribution.params, (std::vector<double>{0.0, 0.1}));
  // Both spellings of one parameter at once is ambiguous.
  const std::string both = error_of("duration_s: 1\nantennas:\n  - name: a\n    position: [0, 0, 1]\n"
                                    "    noisephi: 0.1\n    noise_phi_rad: 0.2\n");
  EXPECT_NE(both.find("give only one of"), std::string::npos) << both;
}

TEST(ScenarioYaml, HoppingAndPhaseOffsets) {
  const Scenario s = parse_scenario(R"(duration_s: 1
antennas:
  - name: a
    position: [0, 0, 1]
    hopping: eu
    phase_offsets_rad: [0.1, 0.2, 0.3, 0.4]
    hop_dwell_s: 0.2
)", "s.yaml");
  EXPECT_EQ(s.antennas[0].reader.frequencies_hz, (std::vector<double>{865.7e6, 866.3e6, 866.9e6, 867.5e6}));
  EXPECT_EQ(s.antennas[0].reader.phase_offsets_rad, (std::vector<double>{0.1, 0.2, 0.3, 0.4}));
  EXPECT_EQ(s.antennas[0].reader.hop_dwell_s, 0.2);
  const std::string e = error_of(R"(duration_s: 1
antennas:
  - name: a
    position: [0, 0, 1]
    frequencies_hz: [865.7e6, 866.3e6]
    phase_offsets_rad: [0.1]
)");
  EXPECT_NE(e.find("s.yaml:6: field 'antennas[0].phase_offsets_rad'"), std::string::npos) << e;
}

TEST(ScenarioYaml, HardwareEffects) {
  const Scenario s = parse_scenario(R"(duration_s: 1
antennas:
  - name: a
    position: [0, 0, 1]
    frequencies_hz: [920.625e6, 921.125e6]
    phase_centre_offset_m: [0.01, -0.02, 0.03]
    phase_pattern: {azimuth_rad: [0.1, -0.2], elevation_rad: [0.05]}
    snr_at_sensitivity_db: 8
    read_probability: [0.5, 0.9]
tags:
  - name: t
    position: [1, 0, 1]
    phase_pattern: {azimuth_rad: [0.3]}
)", "s.yaml");
  const ReaderParams& r = s.antennas[0].reader;
  EXPECT_EQ(r.phase_centre_offset_m, Vec3(0.01, -0.02, 0.03));
  EXPECT_EQ(r.phase_pattern.azimuth_rad, (std::vector<double>{0.1, -0.2}));
  EXPECT_EQ(r.phase_pattern.elevation_rad, (std::vector<double>{0.05}));
  EXPECT_EQ(r.snr_at_sensitivity_db, 8.0);
  EXPECT_EQ(r.read_probability, (std::vector<double>{0.5, 0.9}));
  EXPECT_EQ(s.tags[0].tag.phase_pattern.azimuth_rad, (std::vector<double>{0.3}));
  const std::string bad_key = error_of(R"(duration_s: 1
antennas:
  - name: a
    position: [0, 0, 1]
    phase_pattern: {azimuth: [0.1]}
)");
  EXPECT_NE(bad_key.find("s.yaml:5: field 'antennas[0].phase_pattern.azimuth'"), std::string::npos) << bad_key;
  const std::string bad_p = error_of(R"(duration_s: 1
antennas:
  - name: a
    position: [0, 0, 1]
    read_probability: [0.5, 0.5, 0.5]
)");
  EXPECT_NE(bad_p.find("read_probability"), std::string::npos) << bad_p;
}

TEST(ScenarioYaml, TagPhaseRippleIsDrawnOncePerTagFromTheFilesSeed) {
  const std::string text = R"(duration_s: 1
seed: 5
antennas:
  - name: a
    position: [0, 0, 1]
tags:
  - {name: t1, position: [1, 0, 1], phase_pattern: {ripple_rms_rad: 0.35, ripple_scale_deg: 30, ripple_spread: 0.6}}
  - {name: t2, position: [1, 1, 1], phase_pattern: {ripple_rms_rad: 0.35, ripple_scale_deg: 30, ripple_spread: 0.6}}
  - {name: t3, position: [1, 2, 1]}
)";
  const Scenario s = parse_scenario(text, "s.yaml");
  const PhasePattern& p1 = s.tags[0].tag.phase_pattern;
  const PhasePattern& p2 = s.tags[1].tag.phase_pattern;
  ASSERT_EQ(p1.ripple_cos_rad.size(), 6u);  // 30°: harmonics 3…6 of the half-space
  EXPECT_EQ(p1.ripple_cos_rad[0], 0.0);
  EXPECT_NE(p1.ripple_cos_rad[3], 0.0);
  EXPECT_NE(p1.ripple_cos_rad, p2.ripple_cos_rad);  // each tag its own
  EXPECT_TRUE(s.tags[2].tag.phase_pattern.empty());
  EXPECT_EQ(parse_scenario(text, "s.yaml").tags[0].tag.phase_pattern.ripple_cos_rad, p1.ripple_cos_rad);
  std::string other = text;
  other.replace(other.find("seed: 5"), 7, "seed: 6");
  EXPECT_NE(parse_scenario(other, "s.yaml").tags[0].tag.phase_pattern.ripple_cos_rad, p1.ripple_cos_rad);
  for (const char* bad : {"ripple_rms_rad: -0.1", "ripple_rms_rad: .nan", "ripple_scale_deg: 0.5", "ripple_spread: 3"}) {
    std::string t = text;
    t.replace(t.find("ripple_rms_rad: 0.35, ripple_scale_deg: 30, ripple_spread: 0.6"), 62, bad);
    const std::string e = error_of(t);
    EXPECT_NE(e.find("s.yaml:7: field 'tags[0].phase_pattern.ripple_"), std::string::npos) << bad << ": " << e;
  }
}

// A calibrated antenna (rfidray calibrate's file) is simulated as measured: phase centre, pattern (the
// calibration's own basis, loc::pattern_basis) and carrier offsets give the phase the calibration model predicts.
TEST(ScenarioYaml, AntennaFileDrivesTheSimulation) {
  loc::AntennaCalibration cal;
  cal.antenna = "a";
  cal.phase_centre_offset_m = Vec3(0.03, -0.02, 0.0);
  cal.frequencies_hz = {920.625e6, 921.125e6};
  cal.carrier_offsets_rad = {0.0, 0.7};
  cal.carrier_offsets_sd_rad = {0.0, 0.01};
  cal.pattern_rad = {0.4, 0.2, -0.3, 0.15, 0.1};
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "rfidray_antenna_file_test";
  std::filesystem::create_directories(dir);
  {
    std::ofstream out(dir / "ant.yaml");
    io::write_antenna_file(out, cal);
  }
  const std::string text = R"(duration_s: 0.2
antennas:
  - name: a
    model: physical
    frequencies_hz: [920.625e6, 921.125e6]
    hop_dwell_s: 0.1
    update_rate: 10
    noisephi: 0
    noise_rssi_db: 0
    phase_bits: 0
    position: [0, 0, 0]
    yaw_deg: 90
    antenna_file: ant.yaml
tags:
  - {name: t, position: [0.4, 0.8, 0.3]}
)";
  const Scenario s = parse_scenario(text, (dir / "s.yaml").string());
  const ReaderParams& r = s.antennas[0].reader;
  EXPECT_EQ(r.phase_centre_offset_m, cal.phase_centre_offset_m);
  EXPECT_EQ(r.phase_offsets_rad, (std::vector<double>{0.0, 0.7}));
  const SimulationResult res = simulate(s, IdealChannel{});
  ASSERT_EQ(res.antennas[0].reads.size(), 3u);  // t = 0, 0.1, 0.2: carriers 0, 1, 0
  for (const ReadRecord& rec : res.antennas[0].reads) {
    const Vec3 centre = cal.phase_centre(rec.antenna_pose.position, rec.antenna_pose.orientation);
    double az = 0, el = 0;
    loc::direction_in_frame(centre, rec.antenna_pose.orientation, Vec3(0.4, 0.8, 0.3), az, el);
    const double expected = cal.carrier_offsets_rad[rec.hop_index] +
                            4 * kPi * (Vec3(0.4, 0.8, 0.3) - centre).norm() / wavelength_m(rec.frequency_hz) +
                            cal.pattern_phase_rad(az, el);
    EXPECT_NEAR(std::remainder(rec.reading.phase_rad - expected, kTwoPi), 0.0, 1e-9) << rec.hop_index;
  }
  // A carrier the calibration does not know, and a key that would say the same thing twice, are errors.
  std::string wrong_carrier = text;
  wrong_carrier.replace(wrong_carrier.find("921.125e6]"), 10, "866.3e6]");
  try {
    parse_scenario(wrong_carrier, (dir / "s.yaml").string());
    FAIL() << "uncalibrated carrier accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("not among the calibrated"), std::string::npos) << e.what();
  }
  std::string both = text;
  both.insert(both.find("    antenna_file"), "    phase_centre_offset_m: [0, 0, 0]\n");
  try {
    parse_scenario(both, (dir / "s.yaml").string());
    FAIL() << "antenna_file and phase_centre_offset_m both accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("give either antenna_file"), std::string::npos) << e.what();
  }
  std::filesystem::remove_all(dir);
}

TEST(ScenarioYaml, MotionKinds) {
  const Scenario s = parse_scenario(R"(duration_s: 30
robots:
  - name: r1
    waypoints: [[0, 0], [0, 5]]
    wheel_speed_rad_s: 4.0
    wheel_radius_m: 0.1
    track_width_m: 0.5
    turn_wheel_speed_rad_s: 2.0
antennas:
  - name: on_robot
    robot: r1
    mount: {position: [0.1, 0, 0.3], yaw_deg: 90}
    mast: {z_min_m: 0.5, z_max_m: 1.5, speed_m_s: 0.2}
  - name: walker
    waypoints: [[0, 0, 1], [4, 0, 1]]
    speed_m_s: 1.0
    start_s: 2
tags:
  - name: mover
    waypoints: [[1, 1, 1], [1, 3, 1]]
    speed_m_s: 0.5
    start_s: 3
)", "s.yaml");
  ASSERT_EQ(s.robots.size(), 1u);
  EXPECT_NEAR(s.robots[0].drive.drive_wheel_speed_rad_s, 4.0, 0.0);
  EXPECT_NEAR(s.robots[0].drive.turn_wheel_speed_rad_s, 2.0, 0.0);
  EXPECT_EQ(s.antennas[0].motion.kind, MotionSpec::Kind::kRobot);
  ASSERT_TRUE(s.antennas[0].motion.mast.has_value());
  EXPECT_EQ(s.antennas[0].motion.mast->z_max_m, 1.5);
  EXPECT_EQ(s.antennas[1].motion.kind, MotionSpec::Kind::kWaypoints);
  EXPECT_EQ(s.antennas[1].start_s, 2.0);
  EXPECT_EQ(s.tags[0].motion.kind, MotionSpec::Kind::kWaypoints);
  const SceneMotion m = build_motion(s);
  // The robot drives 5 m at v = r·ω = 0.4 m/s; the antenna rides it on the mast.
  const Pose p = m.antennas[0]->pose_at(2.0);
  EXPECT_NEAR(p.position.y(), 0.8 + 0.1, 1e-12);  // mount x = 0.1 m is along the robot's heading (+Y)
  EXPECT_NEAR(p.position.x(), 0.0, 1e-12);
  EXPECT_NEAR(p.position.z(), mast_height_m(*s.antennas[0].motion.mast, 2.0) + 0.3, 1e-12);
  EXPECT_NEAR(m.tags[0]->pose_at(5.0).position.y(), 2.0, 1e-12);  // started at 3 s, 0.5 m/s
}

TEST(ScenarioYaml, TurnRateConvertsToWheelSpeedsByEq8) {
  const Scenario s = parse_scenario(R"(robot:
  waypoints: [[0, 0], [1, 0], [1, 1]]
  speed_m_s: 0.5
  wheel_radius_m: 0.2
  track_width_m: 0.6
  turn_rate_rad_s: 0.25
antennas:
  - {name: a, robot: robot}
)", "s.yaml");
  const DifferentialDriveParams& d = s.robots[0].drive;
  EXPECT_NEAR(d.turn_wheel_speed_rad_s, 0.25 * 0.6 / (2 * 0.2), 1e-15);
  const SceneMotion m = build_motion(s);
  // 2 m at 0.5 m/s and a quarter turn at 0.25 rad/s.
  EXPECT_NEAR(scenario_duration_s(s, m), 2.0 / 0.5 + (kPi / 2) / 0.25, 1e-12);
}

TEST(ScenarioYaml, ErrorsNameFileLineAndField) {
  struct Case {
    std::string text, expected;
  };
  const std::vector<Case> cases = {
      {"duration_s: 1\nantennas:\n  - name: a\n    position: [0, 0, 1]\n    frequency: -1\n",
       "s.yaml:5: field 'antennas[0].frequency': must be > 0 (got -1)"},
      {"duration_s: 1\nantennas:\n  - name: a\n    position: [0, 0, 1]\n    frequncy: 1e9\n",
       "s.yaml:5: field 'antennas[0].frequncy': unknown key 'frequncy' (did you mean 'frequency'?)"},
      {"duration_s: 1\nantenas: []\n", "s.yaml:2: field 'antenas': unknown key 'antenas' (did you mean 'antennas'?)"},
      {"duration_s: 1\nantennas:\n  - name: a\n    position: [0, 0, 1]\n    optional_distribution: gauss\n",
       "s.yaml:5: field 'antennas[0].optional_distribution': unknown distribution 'gauss'"},
      {"duration_s: 1\nantennas:\n  - name: a\n    position: [0, 0, 1]\n    optional_distribution: gamma\n"
       "    optional_distribution_params: [1, -2]\n",
       "s.yaml:6: field 'antennas[0].optional_distribution_params'"},
      {"duration_s: 1\nantennas:\n  - name: a\n    position: [0, 0]\n", "s.yaml:4: field 'antennas[0].position': needs 3"},
      {"duration_s: 1\nantennas:\n  - name: a\n    position: [0, 0, x]\n",
       "s.yaml:4: field 'antennas[0].position[2]': must be a number (got 'x')"},
      {"duration_s: 1\nantennas:\n  - name: a\n    robot: rover\n", "s.yaml:4: field 'antennas[0].robot': unknown robot 'rover'"},
      {"duration_s: 1\nantennas:\n  - name: a\n", "s.yaml:3: field 'antennas[0].position': is required"},
      {"duration_s: 1\nantennas:\n  - {name: a, position: [0, 0, 1]}\n  - {name: a, position: [1, 0, 1]}\n",
       "s.yaml:4: field 'antennas[1].name': duplicate antenna name 'a'"},
      {"duration_s: 1\nantennas:\n  - {name: tags, position: [0, 0, 1]}\n", "field 'antennas[0].name': 'tags' is reserved"},
      {"duration_s: 1\nantennas:\n  - {name: a, position: [0, 0, 1], mast: {z_min_m: 2, z_max_m: 1, speed_m_s: 1}}\n",
       "s.yaml:3: field 'antennas[0].mast.z_max_m': must be >= z_min_m"},
      {"duration_s: 1\nchannel: raytraced\nantennas:\n  - {name: a, position: [0, 0, 1]}\n",
       "s.yaml:2: field 'channel': unknown channel 'raytraced'"},
      {"duration_s: -2\nantennas:\n  - {name: a, position: [0, 0, 1]}\n", "s.yaml:1: field 'duration_s': must be >= 0"},
      {"antennas:\n  - {name: a, position: [0, 0, 1]}\ntags:\n  - {name: t, waypoints: [[0, 0, 0], [1, 0, 0]]}\n",
       "s.yaml:4: field 'tags[0].speed_m_s': is required with waypoints"},
      {"duration_s: 1\nscene:\n  meshes:\n    - {file: does_not_exist.obj}\nantennas:\n  - {name: a, position: [0, 0, 1]}\n",
       "s.yaml:4: field 'scene.meshes[0].file': no such file"},
      {"duration_s: 1\nantennas:\n  - name: a\n    position: [0, 0, 1]\n    update_rate: .nan\n",
       "s.yaml:5: field 'antennas[0].update_rate': must be a finite number"},
  };
  for (const Case& c : cases) {
    const std::string e = error_of(c.text);
    EXPECT_NE(e.find(c.expected), std::string::npos) << "expected: " << c.expected << "\n     got: " << e;
  }
  const std::string malformed = error_of("antennas:\n  - name: a\n    position: [0, 0, 1\n");
  // "s.yaml:LINE:COLUMN: malformed YAML: ..." (yaml-cpp reports the line where it notices, here 4).
  EXPECT_EQ(malformed.rfind("s.yaml:4:", 0), 0u) << malformed;
  EXPECT_NE(malformed.find(": malformed YAML"), std::string::npos) << malformed;
  try {
    load_scenario("/nonexistent/scenario.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scenario.yaml: cannot open"), std::string::npos);
  }
}

// scene.materials[].solid: a wall as a closed box (RadioMaterial::solid); a boolean, or an error naming it.
TEST(ScenarioYaml, SolidMaterials) {
  const std::string head = "duration_s: 1\nantennas:\n  - {name: a, position: [0, 0, 1]}\nscene:\n  materials:\n";
  const Scenario s = parse_scenario(head + "    - {name: block, relative_permittivity: 5.3, conductivity_s_m: 0.03, "
                                           "thickness_m: 0.2, solid: true}\n"
                                           "    - {name: sheet, relative_permittivity: 2.7}\n", "s.yaml");
  ASSERT_EQ(s.scene.materials.size(), 2u);
  EXPECT_TRUE(s.scene.materials[0].solid);
  EXPECT_DOUBLE_EQ(s.scene.materials[0].thickness_m, 0.2);
  EXPECT_FALSE(s.scene.materials[1].solid);
  const std::string e = error_of(head + "    - {name: block, relative_permittivity: 5.3, solid: maybe}\n");
  EXPECT_NE(e.find("s.yaml:6: field 'scene.materials[0].solid'"), std::string::npos) << e;
}

TEST(ScenarioYaml, DurationRequiredWhenNothingEnds) {
  const Scenario s = parse_scenario("antennas:\n  - {name: a, position: [0, 0, 1]}\n", "s.yaml");
  EXPECT_FALSE(s.duration_s.has_value());
  EXPECT_THROW(scenario_duration_s(s, build_motion(s)), InputError);
}

}  // namespace
}  // namespace rfidray::io

namespace rfidray::io {
namespace {

TEST(ScenarioYaml, ChannelOptionsAndAuto) {
  const std::string base = "antennas:\n  - {name: a, position: [0, 0, 1]}\nduration_s: 1\n";
  const Scenario s = parse_scenario(base +
                                        "channel: auto\n"
                                        "channel_options:\n"
                                        "  candidate_rays: 4096\n"
                                        "  drop_below_db: 30\n"
                                        "  max_path_length_m: 25\n"
                                        "  auto_phase_tolerance_rad: 0.1\n"
                                        "  auto_sample_links: 500\n",
                                    "s.yaml");
  EXPECT_EQ(s.channel, ChannelLevel::kAuto);
  EXPECT_EQ(*s.channel_options.candidate_rays, 4096);
  EXPECT_EQ(*s.channel_options.drop_below_db, 30.0);
  EXPECT_EQ(s.channel_options.auto_phase_tolerance_rad, 0.1);
  EXPECT_EQ(s.channel_options.auto_rssi_tolerance_db, 0.5);  // default kept
  EXPECT_EQ(s.channel_options.auto_sample_links, 500u);
  EXPECT_FALSE(s.channel_options.candidate_spread.has_value());
  // Located errors: unknown key (with a suggestion), bad values.
  const std::string typo = error_of(base + "channel_options:\n  candidate_ray: 10\n");
  EXPECT_NE(typo.find("s.yaml:5"), std::string::npos) << typo;
  EXPECT_NE(typo.find("candidate_rays"), std::string::npos) << typo;
  EXPECT_NE(error_of(base + "channel_options:\n  drop_below_db: -3\n").find("channel_options.drop_below_db"),
            std::string::npos);
  EXPECT_NE(error_of(base + "channel_options:\n  candidates: smart\n").find("must be exact or exhaustive (got 'smart')"), std::string::npos);
  // "exact" and its former name "fast" both read (the channel factory maps both to CandidateMode::kExact).
  for (const std::string name : {"exact", "fast", "exhaustive"})
    EXPECT_EQ(*parse_scenario(base + "channel_options:\n  candidates: " + name + "\n", "s.yaml").channel_options.candidates,
              name);
  EXPECT_NE(error_of(base + "channel_options:\n  max_path_length_m: 0\n").find("> 0"), std::string::npos);
  // Thin posts: 0 (off) … 1 m; a wider "post" or a negative width names the field and its line.
  EXPECT_EQ(*parse_scenario(base + "channel_options:\n  thin_post_max_width_m: 0\n", "s.yaml")
                 .channel_options.thin_post_max_width_m,
            0.0);
  const std::string wide = error_of(base + "channel_options:\n  thin_post_max_width_m: 2\n");
  EXPECT_NE(wide.find("channel_options.thin_post_max_width_m"), std::string::npos) << wide;
  EXPECT_NE(wide.find("at most 1 m"), std::string::npos) << wide;
  EXPECT_NE(error_of(base + "channel_options:\n  thin_post_max_width_m: -1\n").find("thin_post_max_width_m"),
            std::string::npos);
  // Double diffraction: 0 (off) … 100 m.
  EXPECT_EQ(*parse_scenario(base + "channel_options:\n  double_diffraction_max_m: 0.5\n", "s.yaml")
                 .channel_options.double_diffraction_max_m,
            0.5);
  EXPECT_FALSE(parse_scenario(base, "s.yaml").channel_options.double_diffraction_max_m);
  const std::string far = error_of(base + "channel_options:\n  double_diffraction_max_m: 200\n");
  EXPECT_NE(far.find("channel_options.double_diffraction_max_m"), std::string::npos) << far;
  EXPECT_NE(error_of(base + "channel_options:\n  double_diffraction_max_m: -1\n").find("double_diffraction_max_m"),
            std::string::npos);
}

}  // namespace
}  // namespace rfidray::io
