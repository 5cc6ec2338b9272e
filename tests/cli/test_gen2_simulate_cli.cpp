// `rfidray simulate` with a Gen2 reader: slot statistics and reads per second per tag printed, the readings CSV
// with the tick model's columns, byte-identical at 1 and 2 threads, and a bad gen2 key naming file:line:field.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/support/run_rfidray.h"
#include "tests/support/scratch_dir.h"

namespace rfidray::cli {
namespace {

std::string slurp(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

const char* kScenario = R"(seed: 3
duration_s: 2
antennas:
  - name: portal
    position: [0, 0, 1]
    gen2: {preset: max_throughput, session: 0, target: AB, q: 2}
  - name: ticks
    position: [0, 3, 1]
tags:
  - {name: a, position: [1, 0, 1]}
  - {name: b, position: [2, 0, 1]}
  - {name: c, position: [3, 0, 1]}
)";

TEST(Gen2SimulateCli, PrintsSlotStatisticsAndKeepsTheCsvColumns) {
  rfidray::testing::ScratchDir dir("gen2_cli");
  const auto scenario = dir.write("s.yaml", kScenario);
  const auto r1 = rfidray::testing::run_rfidray("simulate " + scenario.string() + " --threads 1 -o " + (dir / "o1").string());
  ASSERT_EQ(r1.status, 0) << r1.output;
  EXPECT_NE(r1.output.find("antenna portal (paper model, Gen2)"), std::string::npos) << r1.output;
  EXPECT_NE(r1.output.find("gen2: "), std::string::npos);
  EXPECT_NE(r1.output.find("empty "), std::string::npos);
  EXPECT_NE(r1.output.find("collided "), std::string::npos);
  EXPECT_NE(r1.output.find("reads per second per tag (the 3 tags read)"), std::string::npos) << r1.output;
  EXPECT_NE(r1.output.find(" a:"), std::string::npos);
  const auto r2 = rfidray::testing::run_rfidray("simulate " + scenario.string() + " --threads 2 -o " + (dir / "o2").string());
  ASSERT_EQ(r2.status, 0) << r2.output;
  const std::string portal = slurp(dir / "o1" / "portal.csv");
  EXPECT_EQ(portal, slurp(dir / "o2" / "portal.csv"));
  // The same header as a tick antenna's file.
  const std::string ticks = slurp(dir / "o1" / "ticks.csv");
  EXPECT_EQ(portal.substr(0, portal.find('\n')), ticks.substr(0, ticks.find('\n')));
  // Hundreds of reads in 2 s (three tags, FM0 at 640 kHz), times increasing.
  std::istringstream rows(portal);
  std::string line;
  std::getline(rows, line);
  double last = -1.0;
  size_t n = 0;
  while (std::getline(rows, line)) {
    const double t = std::stod(line.substr(0, line.find(',')));
    EXPECT_GE(t, last);
    last = t;
    ++n;
  }
  EXPECT_GT(n, 300u);
}

TEST(Gen2SimulateCli, BadGen2KeyIsExit2WithFileLineField) {
  rfidray::testing::ScratchDir dir("gen2_cli_bad");
  std::string text = kScenario;
  text.replace(text.find("q: 2"), 4, "q: 2, encoding: miller5");
  const auto scenario = dir.write("s.yaml", text);
  const auto r = rfidray::testing::run_rfidray("simulate " + scenario.string() + " -o " + (dir / "o").string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("s.yaml:6: field 'antennas[0].gen2.encoding'"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace rfidray::cli
