// Readings/truth CSV parsing and `rfidray localize` end to end on a small synthetic CSV.
#include <gtest/gtest.h>

#include "tests/support/run_rfidray.h"

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "io/readings_csv.h"
#include "core/error.h"
#include "localization/synthetic.h"
#include "tests/support/scratch_dir.h"

namespace rfidray::io {
namespace {

namespace fs = std::filesystem;

fs::path temp_dir() { return testing::program_scratch_dir("localize_test"); }

using testing::write_file;

std::string expect_input_error(const fs::path& p, bool truth = false) {
  try {
    if (truth) read_truth_csv(p);
    else read_readings_csv(p);
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError for " << p;
  return "";
}

const std::string kHeader = "time,posx,posy,posz,q1,q2,q3,q4,name,dist,phase,rssi";

TEST(ReadingsReader, MalformedNumberNamesFileLineAndColumn) {
  const fs::path p = temp_dir() / "bad_number.csv";
  write_file(p, kHeader + "\n0,0,0,0,0,0,0,1,t,1,0.5,-50\n0.1,0,0,x0,0,0,0,1,t,1,0.5,-50\n");
  const std::string msg = expect_input_error(p);
  EXPECT_NE(msg.find("bad_number.csv:3:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("posz"), std::string::npos) << msg;
}

TEST(ReadingsReader, WrongFieldCountAndHeaderAndPhaseRange) {
  const fs::path d = temp_dir();
  write_file(d / "fields.csv", kHeader + "\n0,0,0,0,0,0,0,1,t,1,0.5,-50\n\n0,0,0,0,0,0,0,1,t,1,0.5\n");
  EXPECT_NE(expect_input_error(d / "fields.csv").find("fields.csv:4: expected 12 fields, got 11"), std::string::npos);
  write_file(d / "header.csv", "time,posx,posy,posz,q1,q2,q3,q4,name,phase,dist,rssi\n");
  EXPECT_NE(expect_input_error(d / "header.csv").find("header.csv:1:"), std::string::npos);
  write_file(d / "phase.csv", kHeader + "\n0,0,0,0,0,0,0,1,t,1,7.5,-50\n");
  EXPECT_NE(expect_input_error(d / "phase.csv").find("phase.csv:2: column 'phase'"), std::string::npos);
  write_file(d / "quat.csv", kHeader + "\n0,0,0,0,0,0,0,0,t,1,1,-50\n");
  EXPECT_NE(expect_input_error(d / "quat.csv").find("quat.csv:2:"), std::string::npos);
  EXPECT_NE(expect_input_error(d / "missing.csv").find("cannot open"), std::string::npos);
}

TEST(ReadingsReader, TruthFileErrors) {
  const fs::path d = temp_dir();
  write_file(d / "dup.csv", "name,x,y,z\na,1,2,3\na,1,2,3\n");
  EXPECT_NE(expect_input_error(d / "dup.csv", true).find("dup.csv:3: duplicate tag 'a'"), std::string::npos);
  write_file(d / "nan.csv", "name,x,y,z\na,1,nan,3\n");
  EXPECT_NE(expect_input_error(d / "nan.csv", true).find("nan.csv:2:"), std::string::npos);
}

TEST(ReadingsReader, GroupsByAntennaChannelFrequencyAndSortsByTime) {
  const fs::path p = temp_dir() / "groups.csv";
  write_file(p, kHeader + ",antenna,frequency_hz\n"
               "0.2,0,0,0,0,0,0,1,t,1,0.5,-50,a,866.3e6\n"
               "0.1,0,0,0,0,0,0,1,t,1,0.4,-50,a,866.3e6\n"
               "0.1,0,0,0,0,0,0,1,t,1,0.4,-50,a,865.7e6\n"
               "0.1,0,0,0,0,0,0,1,u,1,0.4,-50,b,865.7e6\n");
  const auto tags = group_by_tag({read_readings_csv(p)}, 865.7e6);
  ASSERT_EQ(tags.size(), 2u);
  EXPECT_EQ(tags[0].tag, "t");
  ASSERT_EQ(tags[0].groups.size(), 2u);
  const auto& g = tags[0].groups[1].frequency_hz == 866.3e6 ? tags[0].groups[1] : tags[0].groups[0];
  ASSERT_EQ(g.reads.size(), 2u);
  EXPECT_LT(g.reads[0].time_s, g.reads[1].time_s);
}

// Writes a readings CSV of two tags seen from an L-shaped path, and the truth file.
// `first_name`: the first tag's name (an EPC-length one tests the text table's alignment).
void write_scenario(const fs::path& readings, const fs::path& truth, bool scramble_dist,
                    const std::string& first_name = "tagA") {
  const std::vector<std::pair<std::string, Vec3>> tags{{first_name, Vec3(1.5, 0.5, 2.05)}, {"tagB", Vec3(-3.0, 1.0, 1.85)}};
  const auto path = loc::sample_polyline({Vec3(-1, -3, 1.68), Vec3(-1, 3, 1.68), Vec3(2, 3, 1.68)}, 0.35, 15.0);
  std::ofstream out(readings);
  out << kHeader << ",antenna\n" << std::setprecision(17);
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> junk(0.0, 50.0);
  for (size_t i = 0; i < tags.size(); ++i) {
    loc::SyntheticSpec spec;
    spec.phase_offsets_rad = {0.9};
    const loc::TagReads t = loc::synthesize(tags[i].first, tags[i].second, path, spec);
    for (const auto& r : t.groups[0].reads) {
      const double dist = scramble_dist ? junk(rng) : (tags[i].second - r.antenna_m).norm();
      const auto& q = r.antenna_orientation;
      out << r.time_s << "," << r.antenna_m.x() << "," << r.antenna_m.y() << "," << r.antenna_m.z() << "," << q.x()
          << "," << q.y() << "," << q.z() << "," << q.w() << "," << tags[i].first << "," << dist << "," << r.phase_rad
          << ",-55,mobile\n";
    }
  }
  std::ofstream t(truth);
  t << "name,x,y,z\n";
  for (const auto& [n, p] : tags) t << n << "," << p.x() << "," << p.y() << "," << p.z() << "\n";
}

std::string run(const std::string& args, int& status) {
  const rfidray::testing::CliResult r = rfidray::testing::run_rfidray("localize " + args);
  status = r.status;
  return r.output;
}

nlohmann::json without_times(nlohmann::json j) {
  for (auto& r : j["results"]) r.erase("time_ms");
  for (auto& [k, v] : j["summary"].items()) v.erase("mean_time_ms");
  return j;
}

TEST(LocalizeCli, EndToEndRecoversTagsAndIgnoresDistColumn) {
  const fs::path d = temp_dir();
  write_scenario(d / "r.csv", d / "t.csv", false);
  write_scenario(d / "r_scrambled.csv", d / "t.csv", true);
  int status = 0;
  const std::string args = " --truth " + (d / "t.csv").string() + " --height-known --method all --json";
  const std::string out = run((d / "r.csv").string() + args, status);
  ASSERT_EQ(status, 0) << out;
  const nlohmann::json j = nlohmann::json::parse(out);
  ASSERT_EQ(j["results"].size(), 6u);
  for (const auto& r : j["results"]) {
    ASSERT_EQ(r["status"], "ok") << r.dump();
    EXPECT_LT(r["error_m"].get<double>(), 0.005) << r.dump();
    EXPECT_TRUE(r.contains("time_ms"));
  }
  for (const char* m : {"hyperbolic", "nlls", "sar"}) {
    EXPECT_EQ(j["summary"][m]["failed"], 0);
    EXPECT_LT(j["summary"][m]["max_error_m"].get<double>(), 0.005);
    EXPECT_LE(j["summary"][m]["median_error_m"].get<double>(), j["summary"][m]["max_error_m"].get<double>());
  }
  // The dist column is ground truth: scrambling it must not change a single estimate.
  const std::string scrambled = run((d / "r_scrambled.csv").string() + args, status);
  ASSERT_EQ(status, 0) << scrambled;
  EXPECT_EQ(without_times(j), without_times(nlohmann::json::parse(scrambled)));
}

// The text table's columns stay aligned when a tag name is longer than the default column (a 24-digit EPC):
// every row's method starts where the header's `method` does.
TEST(LocalizeCli, TextTableFitsLongTagNames) {
  const fs::path d = temp_dir();
  const std::string epc = "100000000000000000000004";
  write_scenario(d / "r.csv", d / "t.csv", false, epc);
  int status = 0;
  const std::string out = run((d / "r.csv").string() + " --method nlls", status);
  ASSERT_EQ(status, 0) << out;
  std::istringstream lines(out);
  std::string header, row;
  std::getline(lines, header);
  const size_t method_col = header.find("method");
  ASSERT_NE(method_col, std::string::npos) << out;
  int rows = 0;
  while (std::getline(lines, row) && !row.empty()) {
    ASSERT_GT(row.size(), method_col) << row;
    EXPECT_EQ(row.compare(method_col, 4, "nlls"), 0) << "misaligned row:\n" << header << "\n" << row;
    EXPECT_EQ(row[method_col - 1], ' ') << row;
    ++rows;
  }
  EXPECT_EQ(rows, 2) << out;
  EXPECT_NE(out.find(epc + " "), std::string::npos) << out;
}

TEST(LocalizeCli, MaxUncertaintyIsTheLargestRegionAccepted) {
  const fs::path d = temp_dir();
  write_scenario(d / "r.csv", d / "t.csv", false);
  int status = 0;
  const std::string base = (d / "r.csv").string() + " --truth " + (d / "t.csv").string() + " --height-known --method nlls --json";
  const nlohmann::json j = nlohmann::json::parse(run(base, status));
  ASSERT_EQ(status, 0);
  double smallest = 1.0;
  for (const auto& r : j["results"]) {
    ASSERT_EQ(r["status"], "ok") << r.dump();
    smallest = std::min(smallest, r["uncertainty_m"].get<double>());
  }
  // A limit below every radius makes every result uncertain: the same position and radius, and the reason
  // says by how much.
  std::ostringstream limit;
  limit << smallest / 2.0;
  const nlohmann::json tight = nlohmann::json::parse(run(base + " --max-uncertainty-m " + limit.str(), status));
  ASSERT_EQ(status, 0);
  ASSERT_EQ(tight["results"].size(), j["results"].size());
  for (size_t i = 0; i < tight["results"].size(); ++i) {
    const auto& r = tight["results"][i];
    EXPECT_EQ(r["status"], "uncertain") << r.dump();
    EXPECT_NE(r["detail"].get<std::string>().find("position uncertainty"), std::string::npos) << r.dump();
    ASSERT_FALSE(r["uncertainty_m"].is_null()) << r.dump();
    ASSERT_FALSE(r["x"].is_null()) << r.dump();
    EXPECT_DOUBLE_EQ(r["x"].get<double>(), j["results"][i]["x"].get<double>());
    EXPECT_DOUBLE_EQ(r["uncertainty_m"].get<double>(), j["results"][i]["uncertainty_m"].get<double>());
  }
  EXPECT_EQ(tight["summary"]["nlls"]["ok"], 0);
  EXPECT_EQ(tight["summary"]["nlls"]["uncertain"], j["summary"]["nlls"]["ok"]);
  EXPECT_EQ(tight["summary"]["nlls"]["with_position"]["count"], j["results"].size());
  for (const char* bad : {"0", "-1", "nan", "inf"}) {
    const std::string out = run(base + " --max-uncertainty-m " + bad, status);
    EXPECT_EQ(status, 2) << bad;
    EXPECT_NE(out.find("--max-uncertainty-m"), std::string::npos) << out;
  }
}

TEST(LocalizeCli, MalformedCsvExitsNonZeroWithLine) {
  const fs::path p = temp_dir() / "broken.csv";
  write_file(p, kHeader + "\n0,0,0,0,0,0,0,1,t,1,0.5,-50\n0,0,0,0,0,0,0,1,t,1,zero,-50\n");
  int status = 0;
  const std::string out = run(p.string(), status);
  EXPECT_NE(status, 0);
  EXPECT_NE(out.find("broken.csv:3:"), std::string::npos) << out;
}

TEST(LocalizeCli, HeightKnownNeedsTruth) {
  const fs::path d = temp_dir();
  write_scenario(d / "r2.csv", d / "t2.csv", false);
  int status = 0;
  const std::string out = run((d / "r2.csv").string() + " --height-known", status);
  EXPECT_NE(status, 0);
  EXPECT_NE(out.find("--height-known"), std::string::npos) << out;
}

// A metal wall 0.25 m behind a tag on a 1 m stage, 8 carriers, single-bounce (the issue's SAR case, ray-traced):
// from the phase alone every method says ok ~16 cm off with a ~8 cm radius; with --scenario the scene's extra
// paths bound the bias, and each method is failed (multipath) or within its radius.
void write_wall_scenario(const fs::path& dir, bool wall) {
  write_file(dir / "wall.obj", "v -2 0.95 -1.5\nv 3 0.95 -1.5\nv 3 0.95 1.5\nv -2 0.95 1.5\nf 1 2 3\nf 1 3 4\n");
  write_file(dir / "wall.yaml", std::string(R"(name: wall
seed: 1
channel: single-bounce
model: physical
scene:
  meshes: )") + (wall ? "[{file: wall.obj, material: metal}]" : "[]") + R"(
antennas:
  - name: stage
    frequencies_hz: [920.625e6, 921.125e6, 921.625e6, 922.125e6, 922.625e6, 923.125e6, 923.625e6, 924.125e6]
    hop_dwell_s: 0.125
    update_rate: 100
    tx_power_dbm: 30
    noisephi: 0.05
    pattern: {kind: patch, gain_dbi: 8, beamwidth_deg: 70}
    yaw_deg: 90
    waypoints: [[0.0, 0, 0], [1.0, 0, 0]]
    speed_m_s: 0.04
tags:
  - {name: tag, position: [0.5, 0.7, 0], yaw_deg: -90}
)");
}

nlohmann::json localize_json(const fs::path& dir, const std::string& extra) {
  int status = 0;
  const std::string out = run((dir / "out" / "stage.csv").string() + " --truth " + (dir / "out" / "tags.csv").string() +
                                  " --method all --height-known --mirror-prior boresight --max-range 3 --json " + extra,
                              status);
  EXPECT_EQ(status, 0) << out;
  const size_t brace = out.find('{');
  if (status != 0 || brace == std::string::npos) return nlohmann::json::object();
  return nlohmann::json::parse(out.substr(brace));
}

TEST(LocalizeCli, ScenarioBoundsTheBiasOfAWallBehindTheTag) {
  for (bool wall : {true, false}) {
    const fs::path d = temp_dir() / (wall ? "wall" : "free");
    fs::create_directories(d);
    write_wall_scenario(d, wall);
    const auto sim = rfidray::testing::run_rfidray("simulate " + (d / "wall.yaml").string() + " -o " + (d / "out").string());
    ASSERT_EQ(sim.status, 0) << sim.output;
    const nlohmann::json plain = localize_json(d, "");
    const nlohmann::json known = localize_json(d, "--scenario " + (d / "wall.yaml").string());
    ASSERT_EQ(plain["results"].size(), 3u);
    ASSERT_EQ(known["results"].size(), 3u);
    for (size_t i = 0; i < 3; ++i) {
      const nlohmann::json& p = plain["results"][i];
      const nlohmann::json& k = known["results"][i];
      ASSERT_TRUE(k.contains("multipath_phase_rad")) << k.dump();
      if (wall) {
        // The case the option exists for: phase alone is silently wrong here.
        ASSERT_EQ(p["status"], "ok") << p.dump();
        EXPECT_GT(p["error_m"].get<double>(), p["uncertainty_m"].get<double>()) << p.dump();
        if (k["status"] == "ok") EXPECT_LE(k["error_m"].get<double>(), k["uncertainty_m"].get<double>()) << k.dump();
        else EXPECT_EQ(k["reason"], "multipath from the scene") << k.dump();
        EXPECT_GT(k["multipath_phase_rad"].get<double>(), 0.3) << k.dump();
      } else {
        // Free space: no allowance, the same answer as without the scene.
        EXPECT_LT(k["multipath_phase_rad"].get<double>(), 1e-9) << k.dump();
        EXPECT_EQ(k["status"], p["status"]) << k.dump();
        EXPECT_EQ(k["x"], p["x"]) << k.dump();
        EXPECT_EQ(k["uncertainty_m"], p["uncertainty_m"]) << k.dump();
      }
    }
  }
}

TEST(LocalizeCli, ScenarioErrorsNameTheFile) {
  const fs::path d = temp_dir() / "bad_scenario";
  fs::create_directories(d);
  write_wall_scenario(d, false);
  const auto sim = rfidray::testing::run_rfidray("simulate " + (d / "wall.yaml").string() + " -o " + (d / "out").string());
  ASSERT_EQ(sim.status, 0) << sim.output;
  write_file(d / "broken.yaml", "name: x\nantennas: [\n");
  int status = 0;
  std::string out = run((d / "out" / "stage.csv").string() + " --scenario " + (d / "broken.yaml").string(), status);
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("broken.yaml"), std::string::npos) << out;
  // Reads of an antenna the scenario does not have (two antennas, neither named 'stage').
  std::string text;
  {
    std::ifstream in(d / "wall.yaml");
    std::stringstream ss;
    ss << in.rdbuf();
    text = ss.str();
  }
  const std::string antenna = text.substr(text.find("  - name: stage"), text.find("tags:") - text.find("  - name: stage"));
  std::string other = antenna, another = antenna;
  other.replace(other.find("stage"), 5, "left");
  another.replace(another.find("stage"), 5, "right");
  text.replace(text.find(antenna), antenna.size(), other + another);
  write_file(d / "other.yaml", text);
  out = run((d / "out" / "stage.csv").string() + " --scenario " + (d / "other.yaml").string(), status);
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("antenna 'stage'"), std::string::npos) << out;
  out = run((d / "out" / "stage.csv").string() + " --channel single-bounce", status);
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("--channel"), std::string::npos) << out;
  out = run((d / "out" / "stage.csv").string() + " --scenario " + (d / "wall.yaml").string() + " --channel sideways", status);
  EXPECT_EQ(status, 2) << out;
  EXPECT_NE(out.find("sideways"), std::string::npos) << out;
}

}  // namespace
}  // namespace rfidray::io
