// `rfidray compare` end to end on a short scenario: a ray-traced LoS through an empty scene equals the ideal
// channel (zero phase error and RSSI difference); through the paper warehouse with reflections it does not.
#include <gtest/gtest.h>

#include "tests/support/run_rfidray.h"
#include "tests/support/scratch_dir.h"
#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace {

namespace fs = std::filesystem;

int run(const std::string& args, std::string* out = nullptr) {
  const rfidray::testing::CliResult r = rfidray::testing::run_rfidray(args);
  if (out) *out = r.output;
  return r.status;
}

fs::path scenario(const std::string& name, const std::string& meshes) {
  static const rfidray::testing::ScratchDir dir("compare");
  const fs::path p = dir / name;
  std::ofstream(p) << "seed: 7\nduration_s: 3\nmodel: physical\nscene:\n  meshes: " << meshes << "\n"
                   << "antennas:\n  - name: fixed\n    position: [-1.0, -3.0, 0.8]\n    frequency: 865.7e6\n"
                      "    update_rate: 10\ntags:\n  - {name: a, position: [2.90, -3.03, 2.05]}\n"
                      "  - {name: b, position: [-4.85, -3.03, 1.85]}\n";
  return p;
}

// antenna,tag,reads_ideal,reads_raytraced,both,phase_err_mean,phase_err_rms,phase_err_max_abs,rssi_mean,rssi_rms,...
std::vector<std::vector<std::string>> read_csv(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::vector<std::string>> rows;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string c;
    while (std::getline(ss, c, ',')) cells.push_back(c);
    rows.push_back(cells);
  }
  return rows;
}

TEST(CompareCli, EmptySceneLosEqualsIdealAndTheWarehouseDoesNot) {
  const rfidray::testing::ScratchDir scratch("compare_out");
  const fs::path out = scratch.path();
  std::string text;
  ASSERT_EQ(run("compare " + scenario("empty.yaml", "[]").string() + " --channel los -o " + (out / "empty").string(), &text), 0) << text;
  auto rows = read_csv(out / "empty" / "compare.csv");
  ASSERT_EQ(rows.size(), 2u);
  for (const auto& r : rows) {
    EXPECT_EQ(r[2], r[3]);          // same reads
    EXPECT_GE(std::stoi(r[2]), 30);   // 3 s at 10 Hz, all read (a few metres, free space)
    EXPECT_EQ(std::stod(r[7]), 0.0);  // phase error
    EXPECT_EQ(std::stod(r[9]), 0.0);  // RSSI difference
  }
  EXPECT_TRUE(fs::exists(out / "empty" / "compare.png"));

  const std::string obj = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/paper_warehouse.obj";
  ASSERT_EQ(run("compare " + scenario("wh.yaml", "[{file: " + obj + "}]").string() + " --tags b -o " + (out / "wh").string(), &text), 0) << text;
  rows = read_csv(out / "wh" / "compare.csv");
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_GT(std::stod(rows[0][6]) + std::stod(rows[1][6]), 0.01);  // multipath moves the phase
  EXPECT_NE(text.find("single-bounce"), std::string::npos);

  // The levels above single-bounce: double reflections and diffraction move the phase further (30 ticks × 2
  // tags, ~1 ms per link at full; full-selective is tested against full in tests/raytrace).
  for (const char* level : {"double-bounce", "full"}) {
    ASSERT_EQ(run("compare " + scenario("wh.yaml", "[{file: " + obj + "}]").string() + " --tags b --channel " + level +
                      " -o " + (out / level).string(),
                  &text),
              0)
        << text;
    EXPECT_NE(text.find(std::string("ideal vs ") + level), std::string::npos) << text;
    const auto higher = read_csv(out / level / "compare.csv");
    ASSERT_EQ(higher.size(), 2u);
    EXPECT_NE(std::stod(higher[0][6]) + std::stod(higher[1][6]), std::stod(rows[0][6]) + std::stod(rows[1][6])) << level;
  }

  EXPECT_EQ(run("compare " + scenario("e2.yaml", "[]").string() + " --tags nosuch -o " + (out / "x").string(), &text), 2);
  EXPECT_NE(text.find("nosuch"), std::string::npos);
}

}  // namespace
