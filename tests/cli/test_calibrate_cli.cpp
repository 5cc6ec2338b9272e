// `rfidray calibrate` and the joint-model flags of `rfidray localize` (--antenna-file, uncertainty_m,
// ok_outside_uncertainty, rejected NaN options), end to end on CSVs written from hardware-like reads.
#include <gtest/gtest.h>

#include "tests/support/run_rfidray.h"
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <nlohmann/json.hpp>
#include <random>
#include <set>
#include <sstream>

#include "io/antenna_file.h"
#include "tests/localization/hardware_reads.h"
#include "tests/support/files.h"
#include "tests/support/scratch_dir.h"

namespace rfidray::io {
namespace {

namespace fs = std::filesystem;
using loc::testing::Hardware;

fs::path temp_dir() { return testing::program_scratch_dir("calibrate_test"); }

std::string run(const std::string& args, int& exit_code) {
  const rfidray::testing::CliResult r = rfidray::testing::run_rfidray(args);
  exit_code = r.status;
  return r.output;
}

// One run: three tags in a row 0.6–0.9 m from a 1 m stop-and-go stage, written as readings + truth CSVs.
void write_run(const fs::path& readings, const fs::path& truth, uint64_t seed, double row_y_m,
               double boresight_offset_m = 0.03) {
  Hardware hw;
  hw.truth = loc::testing::example_hardware();
  hw.truth.phase_centre_offset_m.x() = boresight_offset_m;
  hw.noise_rad = 0.1;
  hw.reads_per_stop = 2;
  const auto stage = loc::testing::straight_stage(Vec3(0, 0, 0), 50, 0.02);
  std::ofstream out(readings);
  std::ofstream t(truth);
  out << "time,posx,posy,posz,q1,q2,q3,q4,name,dist,phase,rssi,antenna,frequency_hz,channel\n" << std::setprecision(12);
  t << "name,x,y,z\n";
  for (int i = 0; i < 3; ++i) {
    const Vec3 tag(0.25 + 0.25 * i, row_y_m + 0.05 * i, 0.0);
    hw.tag_offset_rad = 1.3 * i + seed;
    const loc::TagReads reads = loc::testing::hardware_reads("tag" + std::to_string(i), tag, stage, hw, seed * 10 + i);
    for (size_t g = 0; g < reads.groups.size(); ++g)
      for (const auto& r : reads.groups[g].reads) {
        const auto& q = r.antenna_orientation;
        out << r.time_s << "," << r.antenna_m.x() << "," << r.antenna_m.y() << "," << r.antenna_m.z() << "," << q.x()
            << "," << q.y() << "," << q.z() << "," << q.w() << "," << reads.tag << ",0," << r.phase_rad << ",-50,a0,"
            << reads.groups[g].frequency_hz << "," << g << "\n";
      }
    t << reads.tag << "," << tag.x() << "," << tag.y() << "," << tag.z() << "\n";
  }
}

TEST(CalibrateCli, WritesAnAntennaFileThatLocalizeUses) {
  const fs::path d = temp_dir();
  std::string pairs;
  for (int run_index = 0; run_index < 4; ++run_index) {
    const std::string r = (d / ("ref" + std::to_string(run_index) + ".csv")).string();
    const std::string t = (d / ("ref" + std::to_string(run_index) + "_truth.csv")).string();
    write_run(r, t, 20 + run_index, 0.5 + 0.1 * run_index);
    pairs += " --pair " + r + "," + t;
  }
  const fs::path antenna = d / "antenna.yaml";
  int code = 0;
  // No held-out check here (--held-out-folds 0; the remounted runs below have one): each fold is a calibration,
  // and this test runs under the sanitizers too.
  const std::string out =
      run("calibrate" + pairs + " -o " + antenna.string() + " --height-known --held-out-folds 0 --json", code);
  ASSERT_EQ(code, 0) << out;
  const nlohmann::json j = nlohmann::json::parse(out);
  EXPECT_EQ(j["tags_used"], 12);
  const loc::AntennaCalibration c = read_antenna_file(antenna.string());
  EXPECT_EQ(c.antenna, "a0");
  EXPECT_NEAR(c.phase_centre_offset_m.x(), 0.03, 3.0 * c.phase_centre_offset_sd_m.x());
  EXPECT_LT(c.phase_centre_offset_sd_m.x(), 0.03);
  EXPECT_NEAR(c.carrier_offsets_rad[1], 1.1, 3.0 * c.carrier_offsets_sd_rad[1]);
  EXPECT_LT(c.carrier_offsets_sd_rad[1], 0.1);
  // The file and the JSON carry the covariance of the offset and the pattern; its diagonal is the sd's, and
  // the planar fit's offset x and az² curvature are correlated (both bend the wavefront).
  ASSERT_EQ(j["geometry_covariance"].size(), 8u);
  EXPECT_NEAR(c.geometry_covariance(0, 0), std::pow(c.phase_centre_offset_sd_m.x(), 2), 1e-9 * c.geometry_covariance(0, 0));
  EXPECT_NEAR(c.geometry_covariance(5, 5), std::pow(c.pattern_sd_rad[2], 2), 1e-9 * c.geometry_covariance(5, 5));
  EXPECT_NEAR(j["geometry_covariance"][0][5].get<double>(), c.geometry_covariance(0, 5), 1e-9 * std::abs(c.geometry_covariance(0, 5)));
  EXPECT_GT(std::abs(c.geometry_covariance(0, 5)) / std::sqrt(c.geometry_covariance(0, 0) * c.geometry_covariance(5, 5)), 0.3);
  EXPECT_EQ(c.geometry_covariance(2, 2), 0.0);  // z is not fitted with --height-known
  // Its own reference tags localized with and without it: these references carry an offset, so it helps, and
  // calibrate warns only when it does not.
  const auto& refs = j["references_localized"];
  ASSERT_TRUE(refs.is_object()) << j.dump();
  EXPECT_GE(refs["tags"].get<int>(), 10);
  EXPECT_EQ(refs["helps"].get<bool>(),
            refs["median_error_m"].get<double>() < refs["median_error_uncalibrated_m"].get<double>());
  EXPECT_TRUE(refs["helps"].get<bool>()) << refs.dump();
  EXPECT_EQ(out.find("does not localize its own"), std::string::npos) << out;
  EXPECT_TRUE(j["held_out"].is_null()) << j.dump();  // skipped, as asked
  // With one run there is nothing to leave out, and the text says so.
  const std::string one_pair = pairs.substr(0, pairs.find(" --pair", 1));
  const std::string single = run("calibrate" + one_pair + " -o " + (d / "antenna_one.yaml").string() + " --height-known", code);
  ASSERT_EQ(code, 0) << single;
  EXPECT_NE(single.find("held out: not measured"), std::string::npos) << single;
  // Cross-validation over the --pair runs of an antenna remounted between them (phase centre 6 cm back, then 6 cm
  // forward): in two folds, one mounting against the other, what some runs fit does not carry to the others, and
  // calibrate says so in the JSON and warns, naming the medians (the same-mounting case, where it helps, is
  // Calibration.CrossValidationOverRunsSaysWhetherItCarriesToOtherRuns).
  std::string remounted;
  for (int run_index = 0; run_index < 4; ++run_index) {
    const std::string r = (d / ("moved" + std::to_string(run_index) + ".csv")).string();
    const std::string t = (d / ("moved" + std::to_string(run_index) + "_truth.csv")).string();
    write_run(r, t, 40 + run_index, 0.5 + 0.05 * run_index, run_index % 2 ? 0.06 : -0.06);
    remounted += " --pair " + r + "," + t;
  }
  // --all-terms: every term fitted, as the geometry allows (without it calibrate chooses, below).
  const std::string moved = run("calibrate" + remounted + " -o " + (d / "antenna_moved.yaml").string() +
                                    " --height-known --held-out-folds 2 --all-terms --json", code);
  ASSERT_EQ(code, 0) << moved;
  const nlohmann::json jm = nlohmann::json::parse(moved.substr(moved.find('{'), moved.rfind('}') - moved.find('{') + 1));
  const auto& held = jm["held_out"];
  ASSERT_TRUE(held.is_object()) << jm.dump();
  EXPECT_EQ(held["runs"].get<int>(), 4);
  EXPECT_EQ(held["folds"].get<int>(), 2);
  EXPECT_GE(held["tags"].get<int>(), 10);
  EXPECT_EQ(held["helps"].get<bool>(),
            held["median_error_m"].get<double>() < held["median_error_uncalibrated_m"].get<double>());
  EXPECT_FALSE(held["helps"].get<bool>()) << held.dump();
  EXPECT_NE(moved.find("worse than without calibration"), std::string::npos) << moved;
  EXPECT_EQ(moved.find("does not localize its own"), std::string::npos) << moved;  // the held-out verdict suffices
  EXPECT_TRUE(held["models"].empty()) << held.dump();
  // Without --all-terms calibrate cross-validates the simpler models too and keeps the one with the lowest
  // held-out error: here the carrier offsets alone; the offset and the pattern are listed as not fitted, with why.
  const std::string chosen = run("calibrate" + remounted + " -o " + (d / "antenna_chosen.yaml").string() +
                                     " --height-known --held-out-folds 2 --json", code);
  ASSERT_EQ(code, 0) << chosen;
  const nlohmann::json jc = nlohmann::json::parse(chosen.substr(chosen.find('{'), chosen.rfind('}') - chosen.find('{') + 1));
  const auto& models = jc["held_out"]["models"];
  ASSERT_EQ(models.size(), 4u) << jc.dump();
  EXPECT_EQ(models[0]["median_error_m"].get<double>(), held["median_error_m"].get<double>());  // the full model, as above
  EXPECT_EQ(models[2]["terms"].get<std::string>(), "carrier offsets");
  EXPECT_EQ(models[3]["median_error_m"].get<double>(), held["median_error_uncalibrated_m"].get<double>());  // nothing
  // Carrier offsets only or nothing (the two are within a fraction of a millimetre here): the lower is kept.
  const size_t kept = models[3]["median_error_m"].get<double>() <= models[2]["median_error_m"].get<double>() ? 3 : 2;
  EXPECT_TRUE(models[kept]["kept"].get<bool>()) << models.dump();
  EXPECT_LT(models[kept]["median_error_m"].get<double>(), models[0]["median_error_m"].get<double>());
  EXPECT_EQ(jc["held_out"]["median_error_m"].get<double>(), models[kept]["median_error_m"].get<double>());
  EXPECT_EQ(jc["frequencies_hz"].empty(), kept == 3) << jc["frequencies_hz"];
  std::set<std::string> dropped;
  for (const auto& n : jc["not_fitted"])
    if (n["why"].get<std::string>().find("cross-validated over 4 runs in 2 folds") != std::string::npos)
      dropped.insert(n["term"].get<std::string>());
  EXPECT_EQ(dropped, (std::set<std::string>{"dx", "dy", "az", "az2"}));
  EXPECT_EQ(jc["phase_centre_offset_m"][0].get<double>(), 0.0);
  const std::string chosen_file = testing::slurp(d / "antenna_chosen.yaml");
  EXPECT_NE(chosen_file.find("cross-validated"), std::string::npos) << chosen_file;  // the why is in the file too
  EXPECT_EQ(out.find("worse than without calibration"), std::string::npos) << out;

  // Localize another run with and without the antenna file.
  write_run(d / "run.csv", d / "run_truth.csv", 99, 0.65);
  const std::string base = "localize " + (d / "run.csv").string() + " --truth " + (d / "run_truth.csv").string() +
                           " --height-known --mirror-prior boresight --max-range 1.5 --method nlls --json";
  const std::string with = run(base + " --antenna-file " + antenna.string(), code);
  ASSERT_EQ(code, 0) << with;
  const nlohmann::json jw = nlohmann::json::parse(with);
  for (const auto& r : jw["results"]) {
    ASSERT_EQ(r["status"], "ok") << r.dump();
    ASSERT_TRUE(r["uncertainty_m"].is_number()) << r.dump();
    EXPECT_LE(r["error_m"].get<double>(), r["uncertainty_m"].get<double>()) << r.dump();
    EXPECT_LT(r["error_m"].get<double>(), 0.01) << r.dump();
  }
  EXPECT_EQ(jw["summary"]["nlls"]["ok_outside_uncertainty"], 0);
  const nlohmann::json jr = nlohmann::json::parse(run(base, code));
  double with_mean = jw["summary"]["nlls"]["mean_error_m"].get<double>();
  const auto& raw = jr["summary"]["nlls"];
  if (raw["ok"].get<int>() > 0) {
    EXPECT_LT(with_mean, raw["mean_error_m"].get<double>());
  }
  for (const auto& r : jr["results"]) {
    if (r["status"] == "failed") {
      EXPECT_TRUE(r["uncertainty_m"].is_null()) << r.dump();
    }
  }
  // The allowance per band of tag spacing: these rows are 25 cm apart (above half a wavelength), so the file has
  // that band only; localize says which allowance it used, and --tag-spacing-m picks the band when it has one.
  const auto& bands = j["allowance"]["bands"];
  ASSERT_EQ(bands.size(), 1u) << j["allowance"].dump();
  EXPECT_NEAR(bands[0]["spacing_from_m"].get<double>(), 0.5 * 299792458.0 / c.frequencies_hz.front(), 1e-12);
  EXPECT_TRUE(bands[0]["spacing_below_m"].is_null());
  EXPECT_EQ(bands[0]["samples"].get<int>(), j["allowance"]["samples"].get<int>());
  ASSERT_EQ(c.allowance_bands.size(), 1u);  // in the file too
  EXPECT_NE(jw["allowance"].get<std::string>().find("give the tags' spacing"), std::string::npos) << jw["allowance"];
  const nlohmann::json j25 = nlohmann::json::parse(run(base + " --antenna-file " + antenna.string() + " --tag-spacing-m 0.25", code));
  EXPECT_NE(j25["allowance"].get<std::string>().find("m or more apart"), std::string::npos) << j25["allowance"];
  for (const auto& r : j25["results"])
    EXPECT_NEAR(r["radius_parts"]["systematic_rad"].get<double>(), bands[0]["base_rad"].get<double>(), 1e-9) << r.dump();
  const nlohmann::json j8 = nlohmann::json::parse(run(base + " --antenna-file " + antenna.string() + " --tag-spacing-m 0.08", code));
  EXPECT_NE(j8["allowance"].get<std::string>().find("none measured on tags 0.08 m apart"), std::string::npos) << j8["allowance"];
  const std::string no_file = run(base + " --tag-spacing-m 0.08", code);
  EXPECT_EQ(code, 2) << no_file;
  EXPECT_NE(no_file.find("--tag-spacing-m"), std::string::npos) << no_file;
  EXPECT_NE(no_file.find("needs --antenna-file"), std::string::npos) << no_file;
}

// Coverage on the ray-traced path (the unit test CoversTruthOnHardwareLikeReads is the synthetic one): the
// stage of scenes/stage_1m.yaml — single-bounce over its concrete floor, the antenna's hardware effects (phase
// centre offset, azimuth phase slope, noise that grows near sensitivity) — simulated by `rfidray simulate`
// for reference runs and test runs of other seeds and tag positions, calibrated by `rfidray calibrate`, located
// by `rfidray localize --antenna-file`: ≥ 95 % of the true positions within uncertainty_m of the ok estimates.
TEST(CalibrateCli, RayTracedStageWithHardwareEffectsIsCovered) {
  const fs::path d = temp_dir() / "raytraced";
  fs::create_directories(d);
  fs::copy_file(std::string(RFIDRAY_SOURCE_DIR) + "/scenes/floor_4m.obj", d / "floor_4m.obj",
                fs::copy_options::overwrite_existing);
  std::string base;
  {
    std::ifstream in(std::string(RFIDRAY_SOURCE_DIR) + "/scenes/stage_1m.yaml");
    std::stringstream ss;
    ss << in.rdbuf();
    base = ss.str();
  }
  base = base.substr(0, base.find("\ntags:") + 1);
  // 8x fewer reads than the scene file (CI time): 100 reads/s while the stage moves at 4 cm/s.
  base.replace(base.find("update_rate: 400"), 16, "update_rate: 100");
  base.replace(base.find("speed_m_s: 0.02"), 15, "speed_m_s: 0.04");
  auto simulate = [&](const std::string& name, int seed, double y_min_m, double y_span_m) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    std::string text = base;
    text.replace(text.find("seed: 1"), 7, "seed: " + std::to_string(seed));
    text += "tags:\n";
    for (int i = 0; i < 3; ++i) {
      std::ostringstream tag;
      tag << "  - {name: " << name << i << ", position: [" << 0.15 + 0.7 * u(rng) << ", " << y_min_m + y_span_m * u(rng)
          << ", 0], yaw_deg: -90}\n";
      text += tag.str();
    }
    std::ofstream(d / (name + ".yaml")) << text;
    int code = 0;
    const std::string out = run("simulate " + (d / (name + ".yaml")).string() + " -q -o " + (d / name).string(), code);
    EXPECT_EQ(code, 0) << out;
    return " --pair " + (d / name / "stage.csv").string() + "," + (d / name / "tags.csv").string();
  };
  std::string pairs;
  for (int k = 0; k < 3; ++k) pairs += simulate("ref" + std::to_string(k), 101 + k, 0.55, 0.4);
  int code = 0;
  const std::string cal =
      run("calibrate" + pairs + " -o " + (d / "antenna.yaml").string() + " --height-known --held-out-folds 0", code);
  ASSERT_EQ(code, 0) << cal;
  std::map<std::string, int> ok, covered, tags;
  for (int k = 0; k < 3; ++k) {
    const std::string name = "run" + std::to_string(k);
    simulate(name, 1 + k, 0.6, 0.3);
    const std::string out = run("localize " + (d / name / "stage.csv").string() + " --truth " +
                                    (d / name / "tags.csv").string() + " --antenna-file " + (d / "antenna.yaml").string() +
                                    " --method all --height-known --mirror-prior boresight --max-range 3 --json 2>/dev/null",
                                code);
    ASSERT_EQ(code, 0) << out;
    const nlohmann::json j = nlohmann::json::parse(out.substr(out.find('{')));
    for (const auto& r : j["results"]) {
      const std::string m = r["method"];
      ++tags[m];
      if (r["status"] != "ok") continue;
      ++ok[m];
      covered[m] += r["error_m"].get<double>() <= r["uncertainty_m"].get<double>();
      if (!(r["error_m"].get<double>() <= r["uncertainty_m"].get<double>())) ADD_FAILURE() << "outside: " << r.dump();
    }
  }
  for (const char* m : {"nlls", "sar"}) {
    EXPECT_EQ(tags[m], 9) << m;
    EXPECT_GE(ok[m], 8) << m;  // measured: 9 of 9
  }
  for (const char* m : {"hyperbolic", "nlls", "sar"}) {
    std::cout << m << ": " << ok[m] << " of " << tags[m] << " ok, " << covered[m] << " within uncertainty_m\n";
    EXPECT_GE(covered[m], 0.95 * ok[m]) << m;
  }
}

TEST(CalibrateCli, BadInputExitsTwoNamingTheField) {
  const fs::path d = temp_dir();
  write_run(d / "x.csv", d / "x_truth.csv", 5, 0.7);
  int code = 0;
  std::string out = run("localize " + (d / "x.csv").string() + " --frequency-hz nan", code);
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("--frequency-hz"), std::string::npos) << out;
  out = run("calibrate --pair " + (d / "x.csv").string() + " -o " + (d / "a.yaml").string(), code);
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("--pair"), std::string::npos) << out;
  for (const char* folds : {"1", "-2"}) {
    out = run("calibrate --pair " + (d / "x.csv").string() + "," + (d / "x_truth.csv").string() + " -o " +
                  (d / "a.yaml").string() + " --held-out-folds " + folds, code);
    EXPECT_EQ(code, 2) << out;
    EXPECT_NE(out.find("--held-out-folds"), std::string::npos) << out;
    EXPECT_FALSE(fs::exists(d / "a.yaml"));
  }
  std::ofstream(d / "bad.yaml") << "antenna: a0\nphase_centre_offset_m: [0, 0]\n";
  out = run("localize " + (d / "x.csv").string() + " --antenna-file " + (d / "bad.yaml").string(), code);
  EXPECT_EQ(code, 2) << out;
  EXPECT_NE(out.find("bad.yaml:2: field 'phase_centre_offset_m'"), std::string::npos) << out;
}

}  // namespace
}  // namespace rfidray::io
