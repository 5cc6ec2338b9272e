// `rfidray coverage` end to end: the analytic read-range disc, agreement with `rfidray link` at sampled cells, a
// robot pass's bound, identical files from 1 and 2 MPI ranks, and bad input (exit 2).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/units.h"
#include "tests/support/run_rfidray.h"
#include "tests/support/scratch_dir.h"

namespace rfidray {
namespace {

using testing::run_rfidray;
namespace fs = std::filesystem;

const std::string kScenes = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/";

// A scratch directory of one test, removed at its end.
testing::ScratchDir scratch(const std::string& name) { return testing::ScratchDir("coverage_" + name); }

fs::path write(const testing::ScratchDir& dir, const std::string& name, const std::string& text) {
  return dir.write(name, text);
}

struct Row {
  std::string antenna;
  double x, y, z;
  std::string p, rssi, err, bound;  // as written (may be empty)
  std::string outside, validity_error;
};

std::vector<Row> read_csv(const fs::path& f) {
  std::ifstream in(f);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "antenna,x,y,z,read_probability,rssi_dbm,phase_error_rad,localization_bound_m,outside_validity,"
                  "validity_error");
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> c;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) c.push_back(cell);
    while (c.size() < 10) c.push_back("");
    rows.push_back({c[0], std::stod(c[1]), std::stod(c[2]), std::stod(c[3]), c[4], c[5], c[6], c[7], c[8], c[9]});
  }
  return rows;
}

using testing::slurp;

// One isotropic antenna 1 m over an empty floor, tags in its horizontal plane, line of sight: the physical
// model reads iff P_tx·|h|² ≥ chip sensitivity and P_tx·K·|h|⁴ ≥ reader sensitivity with
// |h|² = (λ/4πD)² (isotropic ends). At 20 dBm the chip (−20 dBm) limits: |h|² ≥ 1e-4, so
// R = λ/(4π)/√1e-4 = 100·λ/(4π) ≈ 2.756 m (the reader side would allow |h|² ≥ 2e-5).
TEST(CoverageCli, EmptyFloorGivesTheLinkBudgetDisc) {
  const auto d = scratch("disc");
  const fs::path sc = write(d, "s.yaml",
                            "channel: los\nmodel: physical\nscene:\n  meshes:\n    - {file: " + kScenes +
                                "floor_4m.obj, scale: [3, 3, 1], material: concrete}\n"
                                "antennas:\n  - {name: a, position: [0.02, 0.03, 1.0], tx_power_dbm: 20}\n"
                                "tags:\n  - {name: t, position: [1, 0, 1], gain_dbi: 0}\n");
  const auto r = run_rfidray("coverage " + sc.string() + " --plane z=1 --extent=-4,-4,4,4 --step 0.1 -o " +
                             (d / "out").string());
  ASSERT_EQ(r.status, 0) << r.output;
  const double lambda = wavelength_m(865.7e6);
  const double radius = 100.0 * lambda / (4.0 * kPi);
  const auto rows = read_csv(d / "out" / "coverage.csv");
  ASSERT_EQ(rows.size(), 80u * 80u);
  size_t inside = 0, misplaced = 0;
  for (const Row& row : rows) {
    const double dist = std::hypot(row.x - 0.02, row.y - 0.03);
    const double p = std::stod(row.p);
    EXPECT_TRUE(p == 0.0 || p == 1.0);
    inside += p == 1.0;
    // Within one grid cell of the analytic circle either answer is acceptable; elsewhere it must be exact.
    if (dist < radius - 0.1 && p != 1.0) ++misplaced;
    if (dist > radius + 0.1 && p != 0.0) ++misplaced;
    // Noise-free RSSI of the physical model: P_tx + 10·log10 K + 20·log10 |h|², to the CSV's 0.001 dB.
    const double h2 = std::pow(lambda / (4.0 * kPi * dist), 2.0);
    EXPECT_NEAR(std::stod(row.rssi), 20.0 + 10.0 * std::log10(0.25) + 20.0 * std::log10(h2), 6e-4);
    EXPECT_EQ(row.err, "0.00000");  // line of sight only: the same phase as free space
    EXPECT_EQ(row.bound, "");       // a fixed antenna: no pass, no bound
  }
  EXPECT_EQ(misplaced, 0u);
  EXPECT_NEAR(double(inside) * 0.01, kPi * radius * radius, 2.0 * kPi * radius * 0.1);
  for (const char* png : {"coverage_a_read_probability.png", "coverage_a_rssi_dbm.png", "coverage_a_phase_error_rad.png"})
    EXPECT_GT(fs::file_size(d / "out" / png), 1000u) << png;
}

// Sampled cells against `rfidray link` on the same scene (ground + wall, single bounce): the same RSSI,
// readability, and phase error against the ideal channel.
TEST(CoverageCli, CellsAgreeWithLink) {
  const auto d = scratch("link");
  const fs::path sc = write(d, "s.yaml",
                            "channel: single-bounce\nmodel: physical\nscene:\n  meshes:\n    - {file: " + kScenes +
                                "ground_wall.obj}\n"
                                "antennas:\n  - {name: a, position: [0, 0, 1], tx_power_dbm: 24}\n"
                                "tags:\n  - {name: t, position: [1, 0, 1.5], gain_dbi: 0}\n");
  const auto r = run_rfidray("coverage " + sc.string() + " --plane z=1.5 --extent=-3,-3,4.6,3 --step 0.4 --no-png -q -o " +
                             (d / "out").string());
  ASSERT_EQ(r.status, 0) << r.output;
  const auto rows = read_csv(d / "out" / "coverage.csv");
  ASSERT_GT(rows.size(), 200u);
  int compared = 0, readable = 0;
  for (size_t i = 0; i < rows.size(); i += 37) {
    const Row& row = rows[i];
    char tag[96];
    std::snprintf(tag, sizeof tag, "%.4f,%.4f,%.4f", row.x, row.y, row.z);
    const auto l = run_rfidray("link --json --tx-power 24 --scene " + kScenes + "ground_wall.obj --antenna 0,0,1 --tag=" + tag);
    ASSERT_EQ(l.status, 0) << l.output;
    const auto j = nlohmann::json::parse(l.output.substr(l.output.find('{')));
    const auto& rt = j["raytraced"];
    EXPECT_NEAR(std::stod(row.rssi), rt["rssi_dbm"].get<double>(), 6e-4) << tag;
    EXPECT_EQ(std::stod(row.p), rt["readable"].get<bool>() ? 1.0 : 0.0) << tag;
    const double err = std::abs(wrap_to_pi(j["ideal"]["phase_rad"].get<double>() - rt["phase_rad"].get<double>()));
    EXPECT_NEAR(std::stod(row.err), err, 6e-6) << tag;
    ++compared;
    readable += rt["readable"].get<bool>();
  }
  EXPECT_GE(compared, 6);
  EXPECT_GT(readable, 0);
  EXPECT_LT(readable, compared);  // the sample crosses the edge of the read range
}

// Cells where the level itself cannot be trusted: a 0.6 m metal plate at level full, cells 1 m up on a 6 × 6 m grid.
// Each cell's outside_validity and validity_error are `rfidray link --json`'s verdict on the same link (the
// antenna's pose), the summary line counts them, and the ideal channel is not judged (empty fields), nor is any
// with --no-validity.
TEST(CoverageCli, CellsOutsideTheLevelsValidityAreMarkedAndCounted) {
  const auto d = scratch("validity");
  write(d, "plate.obj", "v 0 0 0\nv 0.6 0 0\nv 0.6 0.6 0\nv 0 0.6 0\nf 1 2 3\nf 1 3 4\n");
  const std::string body = "model: physical\nscene:\n  meshes:\n    - {file: " + (d.path() / "plate.obj").string() +
                           ", material: metal}\nantennas:\n  - {name: a, position: [0.45, -0.8, 0.05], tx_power_dbm: 30}\n"
                           "tags:\n  - {name: t, position: [0, 0.9, -0.05]}\n";
  const fs::path sc = write(d, "s.yaml", "channel: full\n" + body);
  const auto r = run_rfidray("coverage " + sc.string() + " --plane z=1 --extent=-3,-3,3,3 --step 0.5 -o " +
                             (d / "out").string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_GT(fs::file_size(d / "out" / "coverage_a_validity_error.png"), 1000u);  // the map of the estimates
  const auto rows = read_csv(d / "out" / "coverage.csv");
  ASSERT_EQ(rows.size(), 144u);
  size_t outside = 0;
  const Row* flagged = nullptr;
  const Row* ok = nullptr;
  for (const Row& row : rows) {
    ASSERT_TRUE(row.outside == "0" || row.outside == "1") << row.outside;
    ASSERT_FALSE(row.validity_error.empty());
    outside += row.outside == "1";
    if (row.outside == "1" && !flagged) flagged = &row;
    if (row.outside == "0" && !ok) ok = &row;
  }
  ASSERT_TRUE(flagged && ok) << outside << " of 144 outside";
  EXPECT_NE(r.output.find(std::to_string(outside) + " of 144 cells are where level full is outside its validity"),
            std::string::npos)
      << r.output;
  for (const Row* row : {flagged, ok}) {
    char tag[96];
    std::snprintf(tag, sizeof tag, "%.4f,%.4f,%.4f", row->x, row->y, row->z);
    const auto l = run_rfidray("link --json --channel full --material metal --scene " + (d.path() / "plate.obj").string() +
                               " --antenna 0.45,-0.8,0.05 --tag=" + tag);
    ASSERT_EQ(l.status, 0) << l.output;
    const auto v = nlohmann::json::parse(l.output.substr(l.output.find('{')))["validity"];
    EXPECT_EQ(row->outside == "1", !v["level_ok"].get<bool>()) << tag << ": " << v["reason"];
    EXPECT_NEAR(std::stod(row->validity_error), v["estimated_error"].get<double>(), 6e-4) << tag;
  }
  // The ideal channel ignores the scene: not judged.
  const fs::path ideal = write(d, "ideal.yaml", "channel: ideal\n" + body);
  const auto ri = run_rfidray("coverage " + ideal.string() + " --plane z=1 --extent=-3,-3,3,3 --step 1 --no-png -q -o " +
                              (d / "ideal").string());
  ASSERT_EQ(ri.status, 0) << ri.output;
  for (const Row& row : read_csv(d / "ideal" / "coverage.csv")) EXPECT_EQ(row.outside + row.validity_error, "");
  // --no-validity: the same map without the verdicts (and without their summary line).
  const auto rn = run_rfidray("coverage " + sc.string() + " --plane z=1 --extent=-3,-3,3,3 --step 0.5 --no-validity -o " +
                              (d / "none").string());
  ASSERT_EQ(rn.status, 0) << rn.output;
  EXPECT_EQ(rn.output.find("outside its validity"), std::string::npos) << rn.output;
  EXPECT_TRUE(fs::exists(d / "none" / "coverage_a_read_probability.png"));
  EXPECT_FALSE(fs::exists(d / "none" / "coverage_a_validity_error.png"));
  const auto plain = read_csv(d / "none" / "coverage.csv");
  ASSERT_EQ(plain.size(), rows.size());
  for (size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(plain[i].outside + plain[i].validity_error, "");
    EXPECT_EQ(plain[i].p + plain[i].rssi + plain[i].err, rows[i].p + rows[i].rssi + rows[i].err);
  }
}

// A robot pass: a read probability per pass and a localization bound where the pass reads the tag; the
// fixed antenna of the same scenario has none.
TEST(CoverageCli, RobotPassHasALocalizationBound) {
  const auto d = scratch("pass");
  const auto r = run_rfidray("coverage " + kScenes + "paper_warehouse.yaml --tags --pass-step 0.2 --no-png -q -o " +
                             (d / "out").string());
  ASSERT_EQ(r.status, 0) << r.output;
  const auto rows = read_csv(d / "out" / "coverage.csv");
  ASSERT_EQ(rows.size(), 20u);  // 2 antennas × 10 tags
  int bounded = 0;
  for (const Row& row : rows) {
    if (row.antenna == "fixed") EXPECT_EQ(row.bound, "");
    if (row.antenna == "mobile" && std::stod(row.p) > 0.5) {
      ASSERT_NE(row.bound, "") << row.x << "," << row.y;
      EXPECT_GT(std::stod(row.bound), 0.0);
      EXPECT_LT(std::stod(row.bound), 0.05);  // σ_φ = 0.1 rad over metres of aperture: millimetres
      ++bounded;
    }
  }
  EXPECT_GE(bounded, 6);
}

TEST(CoverageCli, MpiRanksWriteIdenticalFiles) {
#ifndef RFIDRAY_MPIRUN
  GTEST_SKIP() << "built without MPI";
#else
  const auto d = scratch("mpi");
  const std::string args = "coverage " + kScenes +
                           "paper_warehouse.yaml --channel single-bounce --model physical --plane z=1.2 --step 0.5 "
                           "--pass-step 1 --no-png -q -o ";
  const auto one = run_rfidray(args + (d / "one").string());
  ASSERT_EQ(one.status, 0) << one.output;
  // OpenMPI's own allocations are reported as leaks by LeakSanitizer in the sanitizer build; rfidray's code
  // on this path runs leak-checked in the 1-rank runs of this file.
  const auto two = run_rfidray(args + (d / "two").string(),
                               std::string("ASAN_OPTIONS=detect_leaks=0 ") + RFIDRAY_MPIRUN +
                                   " -n 2 --oversubscribe --allow-run-as-root ");
  ASSERT_EQ(two.status, 0) << two.output;
  const std::string a = slurp(d / "one" / "coverage.csv"), b = slurp(d / "two" / "coverage.csv");
  EXPECT_GT(a.size(), 10000u);
  EXPECT_EQ(a, b);
#endif
}

TEST(CoverageCli, BadInputExits2) {
  const std::string sc = kScenes + "paper_warehouse.yaml";
  for (const std::string& args : {sc + " --plane z=abc", sc, sc + " --plane z=1 --tags", sc + " --plane z=1 --step 0",
                                  sc + " --plane z=1 --antenna nope", sc + " --plane z=1 --extent 1,2,3",
                                  sc + " --box 0,0,0,1e6,1e6,10 --step 0.001", sc + " --plane z=1 --pass-step -1",
                                  std::string("/nonexistent.yaml --tags"), sc + " --plane z=1 --channel warp"}) {
    const auto r = run_rfidray("coverage " + args + " -o /tmp/rfidray_cov_bad");
    EXPECT_EQ(r.status, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("error"), std::string::npos) << args;
  }
}

}  // namespace
}  // namespace rfidray
