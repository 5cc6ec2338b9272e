// `rfidray simulate --world` and `rfidray link --world` through the real binary: the CSV equals simulate() on
// the imported world in process, link finds the antenna and tag by name, bad uses exit 2 with a message.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "raytrace/channel_factory.h"
#include "adapters/gazebo/gazebo_world.h"
#include "io/readings_csv.h"
#include "io/world_source.h"
#include "core/simulation.h"
#include "tests/support/scratch_dir.h"
#include "tests/support/run_rfidray.h"

namespace rfidray::gazebo {
namespace {

namespace fs = std::filesystem;
const std::string kDir = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/tests/gazebo";
const std::string kWorld = "--world " + kDir + "/rfid_test.world --resource-path " + kDir + "/models";

using CliRun = rfidray::testing::CliResult;
CliRun run(const std::string& args) { return rfidray::testing::run_rfidray(args); }
using testing::slurp;

TEST(WorldCli, SimulateWorldEqualsSimulateOfTheImportedScenario) {
  const testing::ScratchDir scratch("world_cli");
  const fs::path dir = scratch.path();
  const CliRun r = run("simulate " + kWorld + " --materials " + kDir + "/rfid_test_materials.yaml" +
                    " --channel single-bounce --duration 1 --seed 3 -q -o " + dir.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("invalid inertia"), std::string::npos) << r.output;  // shown, not fatal

  WorldOptions o;
  o.file = kDir + "/rfid_test.world";
  o.resource_path = {kDir + "/models"};
  o.materials_file = kDir + "/rfid_test_materials.yaml";
  const GazeboWorld w = load_world(o);
  Scenario s = w.scenario;
  s.seed = 3;
  s.duration_s = 1.0;
  const auto channel = rfidray::make_channel(ChannelLevel::kSingleBounce, s.channel_options, build_scene(w));
  const SimulationResult result = simulate(s, *channel);
  for (size_t a = 0; a < s.antennas.size(); ++a) {
    std::ostringstream expected;
    io::write_readings_csv(expected, s, a, result.antennas[a]);
    EXPECT_EQ(slurp(dir / (s.antennas[a].reader.name + ".csv")), expected.str()) << s.antennas[a].reader.name;
    EXPECT_GT(result.antennas[a].reads.size(), 0u);
  }
}

TEST(WorldCli, LinkWorldByNames) {
  const CliRun r = run("link " + kWorld + " --antenna reader --tag tag_1::link --json");
  ASSERT_EQ(r.status, 0) << r.output;
  const auto j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
  EXPECT_EQ(j["scene"]["triangles"].get<int>(), 1126);
  // reader at (0, 0, 1.5), tag_1 at (3, 0, 1.5): the direct path is 3 m, and the floor reflects at x = 1.5.
  bool los = false, floor = false;
  for (const auto& p : j["raytraced"]["paths"]) {
    if (p["kind"] == "los") los = std::abs(p["length_m"].get<double>() - 3.0) < 1e-9;
    if (p["kind"] == "reflection" && std::abs(p["point"][2].get<double>()) < 1e-9)
      floor = std::abs(p["point"][0].get<double>() - 1.5) < 1e-6;
  }
  EXPECT_TRUE(los) << r.output;
  EXPECT_TRUE(floor) << r.output;
}

TEST(WorldCli, BadUsesExitTwoWithAMessage) {
  CliRun r = run("simulate " + kWorld);
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--duration S is required"), std::string::npos) << r.output;
  r = run("simulate --world /nonexistent.world --duration 1");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("/nonexistent.world: cannot open world file"), std::string::npos) << r.output;
  r = run("simulate --world " + kDir + "/rfid_test.world --duration 1");  // no resource path: model:// fails
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("model://rack_part"), std::string::npos) << r.output;
  r = run("link " + kWorld + " --antenna nosuch --tag tag_1::link");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("neither X,Y,Z nor an antenna of the world (reader, gate)"), std::string::npos) << r.output;
  r = run("gazebo --world " + kDir + "/rfid_test.world --resource-path " + kDir + "/models --topic-prefix rfid");
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.output.find("--topic-prefix"), std::string::npos) << r.output;
}

// The adapters are a plugin beside the binary (adapters/gazebo/plugin.h): a run that reads no world does not load
// Gazebo's libraries, one that does loads them from the plugin, and without the plugin it exits 2 saying so.
TEST(AdaptersPlugin, LoadedOnlyByRunsThatReadAWorld) {
  const std::string obj_scene = " --scene " + std::string(RFIDRAY_SOURCE_DIR) + "/scenes/paper_warehouse.obj";
  const std::string traced = std::string("LD_DEBUG=libs ") + RFIDRAY_BINARY + " link ";
  const testing::CommandResult plain = testing::run_command(traced + obj_scene + " --antenna 0,0,1 --tag 2,0,1");
  ASSERT_EQ(plain.status, 0) << plain.output;
  EXPECT_EQ(plain.output.find("libsdformat12"), std::string::npos);
  EXPECT_EQ(plain.output.find("librfidray_adapters"), std::string::npos);

  const testing::CommandResult world = testing::run_command(traced + kWorld + " --antenna reader --tag tag_1::link");
  ASSERT_EQ(world.status, 0) << world.output;
  EXPECT_NE(world.output.find("librfidray_adapters.so"), std::string::npos);
  EXPECT_NE(world.output.find("libsdformat12"), std::string::npos);
}

TEST(AdaptersPlugin, MissingPluginIsAnErrorNamingIt) {
  const testing::ScratchDir scratch("adapters_plugin");
  const fs::path copy = scratch.path() / "rfidray";  // the binary alone, without librfidray_adapters.so
  fs::copy_file(RFIDRAY_BINARY, copy);
  const std::string out = (scratch.path() / "out").string();
  const testing::CommandResult r = testing::run_command(copy.string() + " simulate " + kWorld + " --duration 1 -q -o " + out);
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("librfidray_adapters.so"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(out + "/reader.csv"));
  // Everything that needs no world still runs.
  const testing::CommandResult plain = testing::run_command(
      copy.string() + " link --scene " + std::string(RFIDRAY_SOURCE_DIR) + "/scenes/paper_warehouse.obj" +
      " --antenna 0,0,1 --tag 2,0,1");
  EXPECT_EQ(plain.status, 0) << plain.output;
}

}  // namespace
}  // namespace rfidray::gazebo
