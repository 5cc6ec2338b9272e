// `rfidray place` end to end: on a small case its choice covers as many cells as the best of all K-subsets
// (found by brute force over `rfidray coverage` of every candidate), the placed scenario runs in `simulate`,
// 1 and 2 MPI ranks give identical files, and bad input exits 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/run_rfidray.h"
#include "tests/support/scratch_dir.h"

namespace rfidray {
namespace {

using testing::run_rfidray;
namespace fs = std::filesystem;

const std::string kScenes = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/";

// A scratch directory of one test, removed at its end.
testing::ScratchDir scratch(const std::string& name) { return testing::ScratchDir("place_" + name); }

using testing::slurp;

std::vector<std::vector<std::string>> csv(const fs::path& f) {
  std::ifstream in(f);
  std::string line;
  std::vector<std::vector<std::string>> rows;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) c.push_back(cell);
    rows.push_back(c);
  }
  return rows;
}

// Six patch antennas (8 dBi, 70°) at the edges of a 12 × 12 m room with a concrete ground, facing in various
// directions; 20 dBm so that each covers only part of the floor plane.
const std::string kMounts =
    "  - {name: w, position: [-6, 0, 2], yaw_deg: 0}\n"
    "  - {name: e, position: [6, 0, 2], yaw_deg: 180}\n"
    "  - {name: s, position: [0, -6, 2], yaw_deg: 90}\n"
    "  - {name: n, position: [0, 6, 2], yaw_deg: -90}\n"
    "  - {name: sw, position: [-6, -6, 2], yaw_deg: 45}\n"
    "  - {name: ne, position: [6, 6, 2], yaw_deg: -135}\n";

std::string scenario(const std::string& antennas) {
  return "channel: los\nmodel: physical\nscene:\n  meshes:\n    - {file: " + kScenes +
         "floor_4m.obj, scale: [3, 3, 1], material: concrete}\nantennas:\n" + antennas;
}

std::string antenna_keys() { return "tx_power_dbm: 17, pattern: {kind: patch, gain_dbi: 8, beamwidth_deg: 70}"; }

TEST(PlaceCli, EqualsBruteForceOverAllSubsets) {
  const auto d = scratch("brute");
  // The candidates as a scenario of their own, for `coverage`; and as a candidates file, for `place`.
  std::string ants;
  std::stringstream m(kMounts);
  std::string line;
  while (std::getline(m, line)) {
    const auto brace = line.find('{');
    ants += line.substr(0, brace + 1) + antenna_keys() + ", " + line.substr(brace + 1) + "\n";
  }
  std::ofstream(d / "all.yaml") << scenario(ants);
  std::ofstream(d / "one.yaml") << scenario("  - {name: tmpl, position: [0, 0, 2], " + antenna_keys() + "}\n");
  std::ofstream(d / "cand.yaml") << "mounts:\n" << kMounts;
  const std::string cells = " --plane z=1 --extent=-6,-6,6,6 --step 0.5 --no-png -q";
  const auto cov = run_rfidray("coverage " + (d / "all.yaml").string() + cells + " -o " + (d / "cov").string());
  ASSERT_EQ(cov.status, 0) << cov.output;
  std::map<std::string, std::set<size_t>> covers;
  std::map<std::string, size_t> index;
  for (const auto& row : csv(d / "cov" / "coverage.csv")) {
    size_t& i = index[row[0]];
    if (std::stod(row[4]) >= 0.9) covers[row[0]].insert(i);
    ++i;
  }
  const std::vector<std::string> names{"w", "e", "s", "n", "sw", "ne"};
  for (size_t k = 1; k <= 3; ++k) {
    size_t best = 0;
    for (unsigned mask = 0; mask < 64; ++mask) {
      if (static_cast<size_t>(__builtin_popcount(mask)) != k) continue;
      std::set<size_t> u;
      for (size_t c = 0; c < 6; ++c)
        if (mask & (1u << c)) u.insert(covers[names[c]].begin(), covers[names[c]].end());
      best = std::max(best, u.size());
    }
    const fs::path out = d / ("place" + std::to_string(k));
    const auto r = run_rfidray("place " + (d / "one.yaml").string() + " --candidates " + (d / "cand.yaml").string() +
                               " -k " + std::to_string(k) + " --min-probability 0.9" + cells + " -o " + out.string());
    ASSERT_EQ(r.status, 0) << r.output;
    const auto curve = csv(out / "coverage_vs_k.csv");
    ASSERT_EQ(curve.size(), k);
    EXPECT_EQ(std::stoul(curve.back()[2]), best) << "K = " << k;
    EXPECT_GT(best, 0u);
    // The chosen antennas cover the cells they claim (from the per-candidate coverage).
    std::set<size_t> u;
    for (const auto& row : csv(out / "placement.csv")) u.insert(covers[row[2]].begin(), covers[row[2]].end());
    EXPECT_EQ(u.size(), best);
  }
  EXPECT_LT(covers["w"].size(), index["w"]);  // each candidate alone leaves cells uncovered
  // The placed scenario runs.
  const auto sim = run_rfidray("simulate " + (d / "place3" / "placed.yaml").string() + " --duration 0.2 -q -o " +
                               (d / "sim").string());
  EXPECT_EQ(sim.status, 0) << sim.output << slurp(d / "place3" / "placed.yaml");
}

TEST(PlaceCli, MpiRanksWriteIdenticalFiles) {
#ifndef RFIDRAY_MPIRUN
  GTEST_SKIP() << "built without MPI";
#else
  const auto d = scratch("mpi");
  std::ofstream(d / "cand.yaml") << "grids:\n  - {name: pole, min: [-4, -8, 2.5], max: [1, 6, 2.5], step_m: 2.5, "
                                    "yaw_deg: [0, 180]}\n";
  const std::string args = "place " + kScenes + "paper_warehouse.yaml --tags --candidates " + (d / "cand.yaml").string() +
                           " -k 3 --min-probability 0.5 --no-png -q -o ";
  const auto one = run_rfidray(args + (d / "one").string());
  ASSERT_EQ(one.status, 0) << one.output;
  // See test_coverage_cli.cpp: OpenMPI's own allocations are not rfidray's leaks.
  const auto two = run_rfidray(args + (d / "two").string(), std::string("ASAN_OPTIONS=detect_leaks=0 ") +
                                                                RFIDRAY_MPIRUN + " -n 2 --oversubscribe --allow-run-as-root ");
  ASSERT_EQ(two.status, 0) << two.output;
  for (const char* f : {"placement.csv", "coverage_vs_k.csv", "placed.yaml", "placement_cells.csv"}) {
    EXPECT_FALSE(slurp(d / "one" / f).empty()) << f;
    EXPECT_EQ(slurp(d / "one" / f), slurp(d / "two" / f)) << f;
  }
  // The worst-bound objective gathers each pass's information matrices too.
  std::ofstream(d / "robot.yaml") << "robot_mounts:\n  - {name: r, height_m: [1.2, 1.68], yaw_deg: [-90, 90]}\n";
  const std::string bound_args = "place " + kScenes + "paper_warehouse.yaml --tags --candidates " +
                                 (d / "robot.yaml").string() + " -k 2 --objective worst-bound --pass-step 0.5 --no-png -q -o ";
  const auto b1 = run_rfidray(bound_args + (d / "b1").string());
  ASSERT_EQ(b1.status, 0) << b1.output;
  const auto b2 = run_rfidray(bound_args + (d / "b2").string(), std::string("ASAN_OPTIONS=detect_leaks=0 ") +
                                                                    RFIDRAY_MPIRUN + " -n 2 --oversubscribe --allow-run-as-root ");
  ASSERT_EQ(b2.status, 0) << b2.output;
  for (const char* f : {"placement.csv", "coverage_vs_k.csv", "placed.yaml", "placement_cells.csv"}) {
    EXPECT_FALSE(slurp(d / "b1" / f).empty()) << f;
    EXPECT_EQ(slurp(d / "b1" / f), slurp(d / "b2" / f)) << f;
  }
#endif
}

// A robot in the paper's aisle with patch antennas (physical model over free space): facing right (yaw −90°) an
// antenna reads the east rack's tags, facing left the west rack's, so one antenna localizes one side only.
const std::string kRobotScene =
    "channel: ideal\nmodel: physical\n"
    "robot: {name: p3at, waypoints: [[-1.0, -10.0], [-1.0, 8.0]], speed_m_s: 0.35}\n"
    "tags:\n"
    "  - {name: e1, position: [2.90, 0.57, 2.05]}\n  - {name: e2, position: [2.90, -3.03, 2.05]}\n"
    "  - {name: e3, position: [2.90, -6.75, 2.05]}\n  - {name: e4, position: [2.90, 4.0, 1.2]}\n"
    "  - {name: w1, position: [-4.85, -7.70, 1.85]}\n  - {name: w2, position: [-4.85, -3.03, 1.85]}\n"
    "  - {name: w3, position: [-4.85, 1.44, 1.85]}\n  - {name: w4, position: [-4.85, 5.95, 0.6]}\n"
    "antennas:\n";
std::string robot_antenna(const std::string& name, double height, double yaw) {
  return "  - {name: " + name + ", robot: p3at, mount: {position: [0, 0, " + std::to_string(height) +
         "], rpy_deg: [0, 0, " + std::to_string(yaw) + "]}, tx_power_dbm: 27, noisephi: 0.1, update_rate: 15, "
         "pattern: {kind: patch, gain_dbi: 6, beamwidth_deg: 70}}\n";
}

std::vector<std::string> column(const fs::path& f, size_t c) {
  std::vector<std::string> out;
  for (auto row : csv(f)) {
    row.resize(std::max(row.size(), c + 1));
    out.push_back(row[c]);
  }
  return out;
}

void expect_no_inf_or_nan(const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() != ".csv" && e.path().extension() != ".yaml") continue;
    const std::string text = slurp(e.path());
    EXPECT_EQ(text.find("inf"), std::string::npos) << e.path();
    EXPECT_EQ(text.find("nan"), std::string::npos) << e.path();
  }
}

// A robot mount evaluated over the pass gives, cell by cell, the read probability and the bound that `coverage`
// gives the same antenna in the scenario.
TEST(PlaceCli, RobotMountHasCoveragesBound) {
  const auto d = scratch("robot_same");
  std::ofstream(d / "s.yaml") << kRobotScene << robot_antenna("mobile", 1.68, -90);
  std::ofstream(d / "cand.yaml") << "robot_mounts:\n  - {name: r, height_m: 1.68, yaw_deg: -90}\n";
  const std::string cells = " --tags --pass-step 0.2 --no-png -q";
  const auto cov = run_rfidray("coverage " + (d / "s.yaml").string() + cells + " -o " + (d / "cov").string());
  ASSERT_EQ(cov.status, 0) << cov.output;
  const auto r = run_rfidray("place " + (d / "s.yaml").string() + " --candidates " + (d / "cand.yaml").string() +
                             " -k 1 --objective worst-bound" + cells + " -o " + (d / "place").string());
  ASSERT_EQ(r.status, 0) << r.output;
  const auto bound = column(d / "cov" / "coverage.csv", 7), p = column(d / "cov" / "coverage.csv", 4);
  ASSERT_EQ(bound.size(), 8u);
  EXPECT_EQ(column(d / "place" / "placement_cells.csv", 4), bound);
  EXPECT_EQ(column(d / "place" / "placement_cells.csv", 3), p);
  size_t localized = 0;
  for (const std::string& b : bound) localized += !b.empty();
  EXPECT_EQ(localized, 4u);  // the east tags
  const auto curve = csv(d / "place" / "coverage_vs_k.csv");
  ASSERT_EQ(curve.size(), 1u);
  EXPECT_EQ(curve[0][3], std::to_string(localized));
  EXPECT_EQ(curve[0][4], *std::max_element(bound.begin(), bound.end()));  // same width: text order is numeric order
  // The placed scenario rides the robot and runs.
  const std::string placed = slurp(d / "place" / "placed.yaml");
  EXPECT_NE(placed.find("robot: p3at"), std::string::npos) << placed;
  const auto sim = run_rfidray("simulate " + (d / "place" / "placed.yaml").string() + " --duration 2 -q -o " +
                               (d / "sim").string());
  EXPECT_EQ(sim.status, 0) << sim.output << placed;
  expect_no_inf_or_nan(d / "place");
}

// Worst-bound placement over robot mounts (2 heights × 2 yaws): K = 1 equals brute force over `coverage` of each
// candidate; with K = 2 the joint bound (informations add) is below each chosen antenna's own, and the pair
// localizes at least as many tags as any pair's union of individually localized tags.
TEST(PlaceCli, WorstBoundAgainstCoverageOfEveryCandidate) {
  const auto d = scratch("robot_brute");
  std::string all = kRobotScene;
  const std::vector<std::string> names{"r_0_0_0", "r_0_1_0", "r_1_0_0", "r_1_1_0"};
  for (size_t h = 0; h < 2; ++h)
    for (size_t y = 0; y < 2; ++y) all += robot_antenna(names[2 * h + y], h ? 2.2 : 1.0, y ? 90.0 : -90.0);
  std::ofstream(d / "all.yaml") << all;
  std::ofstream(d / "one.yaml") << kRobotScene << robot_antenna("mobile", 1.68, -90);
  std::ofstream(d / "cand.yaml") << "robot_mounts:\n  - {name: r, robot: p3at, height_m: [1.0, 2.2], yaw_deg: [-90, 90]}\n";
  const std::string cells = " --tags --pass-step 0.2 --no-png -q";
  const auto cov = run_rfidray("coverage " + (d / "all.yaml").string() + cells + " -o " + (d / "cov").string());
  ASSERT_EQ(cov.status, 0) << cov.output;
  std::map<std::string, std::vector<std::string>> bounds;
  for (const auto& row : csv(d / "cov" / "coverage.csv")) bounds[row[0]].push_back(row.size() > 7 ? row[7] : "");
  // K = 1 by brute force: the most localized tags, then the smallest worst bound (fixed-width text compares as
  // numbers).
  size_t best_n = 0;
  std::string best_worst;
  for (const auto& n : names) {
    size_t loc = 0;
    std::string worst;
    for (const auto& b : bounds[n])
      if (!b.empty()) ++loc, worst = std::max(worst, b);
    if (loc > best_n || (loc == best_n && loc > 0 && worst < best_worst)) best_n = loc, best_worst = worst;
  }
  ASSERT_GT(best_n, 0u);
  for (size_t k : {1, 2}) {
    const fs::path out = d / ("k" + std::to_string(k));
    const auto r = run_rfidray("place " + (d / "one.yaml").string() + " --candidates " + (d / "cand.yaml").string() +
                               " -k " + std::to_string(k) + " --objective worst-bound" + cells + " -o " + out.string());
    ASSERT_EQ(r.status, 0) << r.output;
    expect_no_inf_or_nan(out);
    const auto curve = csv(out / "coverage_vs_k.csv");
    ASSERT_EQ(curve.size(), k);
    if (k == 1) {
      EXPECT_EQ(std::stoul(curve[0][3]), best_n);
      EXPECT_EQ(curve[0][4], best_worst);
      continue;
    }
    std::vector<std::string> chosen;
    for (const auto& row : csv(out / "placement.csv")) chosen.push_back(row[2]);
    ASSERT_EQ(chosen.size(), 2u);
    const auto joint = column(out / "placement_cells.csv", 4);
    size_t localized = 0;
    for (size_t t = 0; t < joint.size(); ++t) {
      localized += !joint[t].empty();
      for (const auto& c : chosen)
        if (!bounds[c][t].empty()) {
          ASSERT_FALSE(joint[t].empty()) << t;
          EXPECT_LE(std::stod(joint[t]), std::stod(bounds[c][t]) + 1e-6) << c << " tag " << t;
        }
    }
    EXPECT_EQ(std::stoul(curve[1][3]), localized);
    size_t union_best = 0;
    for (size_t i = 0; i < 4; ++i)
      for (size_t j = i + 1; j < 4; ++j) {
        size_t u = 0;
        for (size_t t = 0; t < joint.size(); ++t) u += !bounds[names[i]][t].empty() || !bounds[names[j]][t].empty();
        union_best = std::max(union_best, u);
      }
    EXPECT_GE(localized, union_best);
    EXPECT_EQ(localized, 8u);  // one antenna facing each rack
  }
}

TEST(PlaceCli, BadInputExits2) {
  const auto d = scratch("bad");
  std::ofstream(d / "cand.yaml") << "mounts:\n  - {name: a, position: [0, 0, 2]}\n";
  std::ofstream(d / "typo.yaml") << "mounts:\n  - {name: a, positon: [0, 0, 2]}\n";
  std::ofstream(d / "empty.yaml") << "template: fixed\n";
  std::ofstream(d / "rob.yaml") << "robot_mounts:\n  - {name: r, height_m: 1.5}\n";
  std::ofstream(d / "rob_bad.yaml") << "robot_mounts:\n  - {name: r, robot: nosuch, height_m: 1.5}\n";
  std::ofstream(d / "rob_noh.yaml") << "robot_mounts:\n  - {name: r, yaw_deg: 90}\n";
  std::ofstream(d / "norobot.yaml") << "antennas:\n  - {name: a, position: [0, 0, 1]}\ntags:\n  - {name: t, position: [1, 0, 1]}\n";
  const std::string sc = kScenes + "paper_warehouse.yaml --tags -o " + (d / "o").string();
  for (const std::string& args :
       {sc + " --candidates " + (d / "cand.yaml").string() + " -k 2", sc + " --candidates " + (d / "typo.yaml").string(),
        sc + " --candidates " + (d / "empty.yaml").string(), sc + " --candidates " + (d / "nope.yaml").string(),
        sc + " --candidates " + (d / "cand.yaml").string() + " --min-probability 1.5",
        sc + " --candidates " + (d / "cand.yaml").string() + " -k 1 --objective best",
        sc + " --candidates " + (d / "cand.yaml").string() + " -k 1 --objective worst-bound",  // no robot mount
        sc + " --candidates " + (d / "rob_bad.yaml").string() + " -k 1", sc + " --candidates " + (d / "rob_noh.yaml").string(),
        (d / "norobot.yaml").string() + " --tags -o " + (d / "o").string() + " --candidates " + (d / "rob.yaml").string() +
            " -k 1"}) {
    const auto r = run_rfidray("place " + args);
    EXPECT_EQ(r.status, 2) << args << "\n" << r.output;
  }
}

}  // namespace
}  // namespace rfidray
