// `rfidray coverage --world` and `rfidray place --world` through the real binary on the Gazebo test world: the
// coverage CSV equals planning::coverage() on the imported world in process, a candidate at the world's gate antenna
// gives that antenna's coverage, and what a world cannot give (robot mounts, a placed scenario file) is said.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "adapters/gazebo/gazebo_world.h"
#include "core/simulation.h"
#include "raytrace/channel_factory.h"
#include "io/coverage_csv.h"
#include "planning/coverage_map.h"
#include "tests/support/run_rfidray.h"
#include "tests/support/scratch_dir.h"

namespace rfidray::gazebo {
namespace {

namespace fs = std::filesystem;
const std::string kDir = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/tests/gazebo";
const std::string kWorld = "--world " + kDir + "/rfid_test.world --resource-path " + kDir + "/models --materials " +
                           kDir + "/rfid_test_materials.yaml";

using CliRun = rfidray::testing::CliResult;
CliRun run(const std::string& args) { return rfidray::testing::run_rfidray(args); }
using testing::slurp;
// A scratch directory of one test, removed at its end.
testing::ScratchDir scratch(const std::string& name) { return testing::ScratchDir("world_plan_" + name); }
// Column c of a CSV (header dropped).
std::vector<std::string> column(const fs::path& f, size_t c) {
  std::ifstream in(f);
  std::string line;
  std::getline(in, line);
  std::vector<std::string> out;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream s(line);
    std::string cell;
    while (std::getline(s, cell, ',')) cells.push_back(cell);
    cells.resize(std::max(cells.size(), c + 1));
    out.push_back(cells[c]);
  }
  return out;
}

TEST(WorldPlanningCli, CoverageWorldEqualsCoverageOfTheImportedWorld) {
  const auto d = scratch("cov");
  const CliRun r = run("coverage " + kWorld + " --channel single-bounce --tags --no-png -q -o " + d.string());
  ASSERT_EQ(r.status, 0) << r.output;

  WorldOptions o;
  o.file = kDir + "/rfid_test.world";
  o.resource_path = {kDir + "/models"};
  o.materials_file = kDir + "/rfid_test_materials.yaml";
  const GazeboWorld w = load_world(o);
  const Scenario& s = w.scenario;
  const SceneMotion motion = build_motion(s);
  const auto channel = make_channel(ChannelLevel::kSingleBounce, s.channel_options, build_scene(w));
  const IdealChannel ideal;
  planning::CoverageCells cells;
  cells.params.clear();
  for (size_t i = 0; i < s.tags.size(); ++i) {
    cells.poses.push_back(motion.tags[i]->pose_at(s.tags[i].start_s));
    cells.params.push_back(s.tags[i].tag);
    cells.param_of.push_back(static_cast<uint32_t>(i));
  }
  std::vector<std::string> names;
  std::vector<planning::CoverageValues> values;
  for (size_t a = 0; a < s.antennas.size(); ++a) {
    names.push_back(s.antennas[a].reader.name);
    values.push_back(planning::coverage(s, motion, a, *channel, ideal, cells));
  }
  std::ostringstream expected;
  io::write_coverage_csv(expected, names, cells, values);
  EXPECT_EQ(slurp(d / "coverage.csv"), expected.str());
  ASSERT_EQ(s.antennas.size(), 2u);  // reader and gate, over both tags
  ASSERT_EQ(s.tags.size(), 2u);
  size_t read = 0;
  for (const auto& v : values)
    for (double p : v.read_probability) read += p > 0.5;
  EXPECT_GT(read, 0u);
}

TEST(WorldPlanningCli, CoveragePlaneOverTheWorld) {
  const auto d = scratch("plane");
  const CliRun r = run("coverage " + kWorld + " --channel los --plane z=1 --step 0.5 --antenna gate -o " + d.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("world 'rfid_test'"), std::string::npos) << r.output;  // the world's summary
  const auto p = column(d / "coverage.csv", 4);
  ASSERT_GT(p.size(), 20u);
  size_t read = 0;
  for (const auto& v : p) read += !v.empty() && std::stod(v) == 1.0;
  EXPECT_GT(read, 0u);
  EXPECT_LT(read, p.size());  // a patch at 27 dBm does not read the whole floor's extent
  // Maps over the world's floor plan, seen from above.
  EXPECT_GT(fs::file_size(d / "coverage_gate_read_probability.png"), 1000u);
}

// A fixed candidate at the gate's pose (model pose (1, 4, 0) + sensor (0, 0, 2), yaw −90°), copying the gate, gives
// the gate's own coverage cell by cell; no placed scenario is written (a world is not a scenario file).
TEST(WorldPlanningCli, PlaceWorldCandidateAtTheGateHasTheGatesCoverage) {
  const auto d = scratch("place");
  const std::string cells = " --channel los --plane z=1 --step 0.5 --no-png -q";
  const CliRun cov = run("coverage " + kWorld + cells + " --antenna gate -o " + (d / "cov").string());
  ASSERT_EQ(cov.status, 0) << cov.output;
  std::ofstream(d / "one.yaml") << "template: gate\nmounts:\n  - {name: g, position: [1, 4, 2], yaw_deg: -90}\n";
  const CliRun one = run("place " + kWorld + cells + " --candidates " + (d / "one.yaml").string() + " -k 1 -o " +
                         (d / "one").string());
  ASSERT_EQ(one.status, 0) << one.output;
  EXPECT_EQ(column(d / "one" / "placement_cells.csv", 3), column(d / "cov" / "coverage.csv", 4));
  EXPECT_FALSE(fs::exists(d / "one" / "placed.yaml"));
  // Robot mounts need a robot, which an imported world does not have.
  std::ofstream(d / "robot.yaml") << "robot_mounts:\n  - {name: r, height_m: 1.5}\n";
  const CliRun bad = run("place " + kWorld + cells + " --candidates " + (d / "robot.yaml").string() + " -k 1 -o " +
                         (d / "bad").string());
  EXPECT_EQ(bad.status, 2) << bad.output;
  EXPECT_NE(bad.output.find("no robot"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace rfidray::gazebo
