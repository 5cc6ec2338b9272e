// `rfidray place` end to end: on a small case its choice covers as many cells as the best of all K-subsets
// (found by brute force over `rfidray coverage` of every candidate), the placed scenario runs in `simulate`,
// 1 and 2 MPI ranks give identical files, and bad input exits 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "tests/support/run_rfidray.h"

namespace rfidray {
namespace {

using testing::run_rfidray;
namespace fs = std::filesystem;

const std::string kScenes = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/";

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("rfidray_place_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

std::string slurp(const fs::path& f) {
  std::ifstream in(f, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

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
  const fs::path d = scratch("brute");
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
  fs::remove_all(d);
}

TEST(PlaceCli, MpiRanksWriteIdenticalFiles) {
#ifndef RFIDRAY_MPIRUN
  GTEST_SKIP() << "built without MPI";
#else
  const fs::path d = scratch("mpi");
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
  for (const char* f : {"placement.csv", "coverage_vs_k.csv", "placed.yaml"}) {
    EXPECT_FALSE(slurp(d / "one" / f).empty()) << f;
    EXPECT_EQ(slurp(d / "one" / f), slurp(d / "two" / f)) << f;
  }
  fs::remove_all(d);
#endif
}

TEST(PlaceCli, BadInputExits2) {
  const fs::path d = scratch("bad");
  std::ofstream(d / "cand.yaml") << "mounts:\n  - {name: a, position: [0, 0, 2]}\n";
  std::ofstream(d / "typo.yaml") << "mounts:\n  - {name: a, positon: [0, 0, 2]}\n";
  std::ofstream(d / "empty.yaml") << "template: fixed\n";
  const std::string sc = kScenes + "paper_warehouse.yaml --tags -o " + (d / "o").string();
  for (const std::string& args :
       {sc + " --candidates " + (d / "cand.yaml").string() + " -k 2", sc + " --candidates " + (d / "typo.yaml").string(),
        sc + " --candidates " + (d / "empty.yaml").string(), sc + " --candidates " + (d / "nope.yaml").string(),
        sc + " --candidates " + (d / "cand.yaml").string() + " --min-probability 1.5"}) {
    const auto r = run_rfidray("place " + args);
    EXPECT_EQ(r.status, 2) << args << "\n" << r.output;
  }
  fs::remove_all(d);
}

}  // namespace
}  // namespace rfidray
