// The ROS 1 pose input end to end, with a ROS master of its own: a fake Gazebo 11 (fake_gazebo11.cpp, its
// own process) plays the paper's robot driving its L path — /gazebo/model_states, /tf (odom → base_link →
// mast_link, the mast sliding up and down), /tf_static (world → odom) and /clock — and `rfidray gazebo
// --input ros` follows it on paper_robot.world, whose antenna block is the seed plugin's, unchanged. Plain
// roscpp subscribers receive every TagArray on the seed's topics, and the bridge's readings CSV equals
// `rfidray simulate paper_robot.yaml` (the same motion) byte for byte.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

#include "adapters/gazebo/live_world.h"
#include "core/mast.h"
#include "io/scenario_yaml.h"
#include "tests/adapters/gazebo/fake_gazebo.h"
#include "tests/support/ros_master.h"

namespace rfidray::gazebo {
namespace {

using namespace fake;
const std::string kRosDir = std::string(RFIDRAY_SOURCE_DIR) + "/tests/adapters/ros";
constexpr double kRate = 15.0;  // both antennas; the run: 23 s (the robot stops at 23.57 s)
constexpr int kTicks = 346;     // k / 15 <= 23
constexpr uint64_t kRosSeed = 11;

using Child = rfidray::testing::RosChild;
using rfidray::testing::have_rosmaster;

void put_pose(std::FILE* f, const Pose& p) {
  std::fprintf(f, " %.17g %.17g %.17g %.17g %.17g %.17g %.17g", p.position.x(), p.position.y(), p.position.z(),
               p.orientation.x(), p.orientation.y(), p.orientation.z(), p.orientation.w());
}

struct ScriptOptions {
  std::vector<double> times;       // one step each
  bool mast_tf = true;             // publish base_link -> mast_link
  std::string extra_model;         // a model_states name the world does not have
  size_t await_after = 0;          // after this many steps, wait for await_ticks TagArrays per antenna
  int await_ticks = 0;
  bool clock = true;               // publish /clock
};

// What Gazebo 11 and the robot's TF publishers send at each step: /tf (odom -> base_link -> mast_link), every
// top-level model of the world in /gazebo/model_states (the robot where it drives), then /clock.
void write_script(const fs::path& path, const ScriptOptions& o) {
  const Scenario s = io::load_scenario(kRosDir + "/paper_robot.yaml");
  const SceneMotion motion = build_motion(s);
  const MastParams mast = *s.antennas[0].motion.mast;
  WorldOptions wo;
  wo.file = kRosDir + "/paper_robot.world";
  const GazeboWorld world = load_world(wo);
  std::FILE* f = std::fopen(path.c_str(), "w");
  ASSERT_NE(f, nullptr);
  if (!o.clock) std::fprintf(f, "noclock\n");
  std::fprintf(f, "static world odom");
  put_pose(f, Pose{});
  std::fprintf(f, "\n");
  for (size_t i = 0; i < o.times.size(); ++i) {
    const double t = o.times[i];
    if (o.await_ticks > 0 && i == o.await_after)
      std::fprintf(f, "await /gazebo/mobile/data %d\nawait /gazebo/fixed/data %d\n", o.await_ticks, o.await_ticks);
    const Pose robot = motion.robots[0]->pose_at(t);
    std::fprintf(f, "step %.17g\ntf odom base_link", t);
    put_pose(f, robot);
    if (o.mast_tf) {
      std::fprintf(f, "\ntf base_link mast_link");
      put_pose(f, Pose{Vec3(0, 0, mast_height_m(mast, t)), Quat::Identity()});
    }
    std::fprintf(f, "\n");
    for (const Entity& e : world.entities) {
      if (e.parent >= 0 || e.kind != Entity::Kind::kModel) continue;
      std::fprintf(f, "model %s", e.name.c_str());
      put_pose(f, e.name == "p3at" ? robot : e.pose);
      std::fprintf(f, "\n");
    }
    if (!o.extra_model.empty()) {
      std::fprintf(f, "model %s", o.extra_model.c_str());
      put_pose(f, Pose{});
      std::fprintf(f, "\n");
    }
  }
  std::fclose(f);
}

// Tick times k / 15 for k = first .. last.
std::vector<double> tick_times(int first, int last) {
  std::vector<double> t;
  for (int k = first; k <= last; ++k) t.push_back(static_cast<double>(k) / kRate);
  return t;
}

// A master of the test's own (tests/support/ros_master.h), on a port from the pid clear of the other test's.
struct RosMaster : rfidray::testing::RosMaster {
  explicit RosMaster(const std::string& name)
      : rfidray::testing::RosMaster(name, 20000 + static_cast<int>((getpid() * 7 + 3) % 20000)) {}
};

int run_simulate(const fs::path& dir, const std::string& duration = "23") {
  BridgeProcess sim({"simulate", kRosDir + "/paper_robot.yaml", "--seed", std::to_string(kRosSeed), "--duration",
                     duration, "-o", (dir / "sim").string(), "-q"},
                    dir / "simulate.log");
  return sim.wait(60000ms);
}


TEST(RosInputEndToEnd, Gazebo11RobotOnTheLPathGivesTheReadingsOfSimulate) {
  if (!have_rosmaster()) GTEST_SKIP() << "rosmaster not installed (Debian package python3-rosmaster)";
  RosMaster ros("ros_input");
  ASSERT_TRUE(ros.up()) << slurp(ros.dir / "rosmaster.log");
  const fs::path& dir = ros.dir;
  write_script(dir / "script.txt", {tick_times(0, kTicks)});  // one past the end: the clock passes the last tick

  Child mobile({RFIDRAY_TAG_ARRAY_LISTENER, "/gazebo/mobile/data", std::to_string(kTicks), "40",
                (dir / "mobile.txt").string()},
               dir / "mobile_listener.log");
  Child fixed({RFIDRAY_TAG_ARRAY_LISTENER, "/gazebo/fixed/data", std::to_string(kTicks), "40",
               (dir / "fixed.txt").string()},
              dir / "fixed_listener.log");
  BridgeProcess bridge({"gazebo", "--input", "ros", "--world", kRosDir + "/paper_robot.world", "--frame",
                        "mobile=mast_link", "--sim-time", "--seed", std::to_string(kRosSeed), "--duration", "23",
                        "--csv", (dir / "bridge").string(), "--connect-timeout", "15", "--idle-timeout", "30",
                        "--tf-timeout", "20"},
                       dir / "bridge.log");
  Child gazebo({RFIDRAY_FAKE_GAZEBO11, (dir / "script.txt").string(), "40"}, dir / "fake_gazebo11.log");

  ASSERT_EQ(bridge.wait(40000ms), 0) << "bridge:\n" << slurp(dir / "bridge.log");
  ASSERT_EQ(gazebo.wait(20000ms), 0) << "fake Gazebo 11:\n" << slurp(dir / "fake_gazebo11.log");
  ASSERT_EQ(mobile.wait(20000ms), 0) << slurp(dir / "mobile_listener.log") << slurp(dir / "bridge.log");
  ASSERT_EQ(fixed.wait(20000ms), 0) << slurp(dir / "fixed_listener.log");

  const int sim = run_simulate(dir);
  ASSERT_EQ(sim, 0) << slurp(dir / "simulate.log");
  for (const std::string antenna : {"mobile", "fixed"}) {
    const std::string expected = slurp(dir / "sim" / (antenna + ".csv"));
    const std::string got = slurp(dir / "bridge" / (antenna + ".csv"));
    const size_t rows = static_cast<size_t>(std::count(expected.begin(), expected.end(), '\n')) - 1;
    EXPECT_GT(rows, 100u) << antenna << ": the robot passes the tags, most ticks read some";
    EXPECT_EQ(got, expected) << antenna << ".csv differs from rfidray simulate's";
    // Every tick arrived as a TagArray, stamped k / 15, carrying the CSV's reads.
    std::istringstream in(slurp(dir / (antenna + ".txt")));
    std::string line;
    int k = 0;
    size_t reads = 0;
    while (std::getline(in, line)) {
      std::istringstream f(line);
      double stamp = 0;
      unsigned ntags = 0;
      f >> stamp >> ntags;
      EXPECT_NEAR(stamp, k / kRate, 1e-9) << antenna << " message " << k;
      reads += ntags;
      ++k;
    }
    EXPECT_EQ(k, kTicks) << antenna;
    EXPECT_EQ(reads, rows) << antenna;
  }
}

// The TF frame of an antenna may sit in its sensor block, in either form; it is no reader parameter.
TEST(RosInputFrames, FrameElementInTheSensorBlockNamesTheTfFrame) {
  const rfidray::testing::ScratchDir dir("frame");
  dir.write("w.world", R"(<?xml version="1.0"?>
<sdf version="1.6"><world name="w"><model name="robot"><link name="mast">
  <sensor name="seed" type="rfid"><update_rate>10</update_rate>
    <plugin name="p" filename="librfid_antenna.so"><range>4</range><frame>mast_link</frame></plugin></sensor>
  <sensor name="native" type="custom"><update_rate>10</update_rate>
    <rfid_antenna><model>physical</model><frame>arm_tool</frame></rfid_antenna></sensor>
  <sensor name="plain" type="rfid"><update_rate>10</update_rate></sensor>
</link></model></world></sdf>
)");
  WorldOptions wo;
  wo.file = (dir / "w.world").string();
  const GazeboWorld w = load_world(wo);
  ASSERT_EQ(w.antenna_mounts.size(), 3u);
  EXPECT_EQ(w.antenna_mounts[0].frame, "mast_link");
  EXPECT_EQ(w.antenna_mounts[1].frame, "arm_tool");
  EXPECT_EQ(w.antenna_mounts[2].frame, "");
  EXPECT_EQ(w.scenario.antennas[0].reader.range_m, 4.0);
  EXPECT_EQ(w.scenario.antennas[1].reader.model, ReaderModelKind::kPhysical);
  for (const std::string& warning : w.warnings) EXPECT_EQ(warning.find("frame"), std::string::npos) << warning;
}

// The tick core both pose inputs drive (live_world.h): a model moved by set_entity_pose moves its collisions
// (the traced scene is rebuilt before the next traced tick, and only when a pose changed), and an antenna with
// a pose provider reads from the provider's pose.
TEST(RosInputFrames, MovedModelsRebuildTheSceneAndProvidersPlaceAntennas) {
  WorldOptions wo;
  wo.file = kRosDir + "/paper_robot.world";
  GazeboWorld w = load_world(wo);
  const int robot = w.find("p3at");
  ASSERT_GE(robot, 0);
  LiveOptions lo;
  lo.channel = ChannelLevel::kLosBlocked;
  for (AntennaSpec& a : w.scenario.antennas) a.reader.model = ReaderModelKind::kPhysical;
  LiveWorld live(std::move(w), lo);
  const Pose mast_pose{Vec3(-1.0, -9.0, 1.5), Quat::Identity()};
  live.set_antenna_pose_provider([&](size_t a, double) -> std::optional<Pose> {
    return a == 0 ? std::optional<Pose>(mast_pose) : std::nullopt;
  });
  std::vector<TickReadings> ticks;
  auto sink = [&](const TickReadings& t) { ticks.push_back(t); };
  live.advance(0.0, sink);
  live.advance(0.05, sink);  // tick 0 of both antennas
  EXPECT_EQ(live.scene_builds(), 1u);
  Pose moved = live.world().entities[robot].pose;
  moved.position.x() += 2.0;
  live.set_entity_pose(robot, moved);
  live.advance(0.1, sink);  // tick 1 at 1/15 s
  EXPECT_EQ(live.scene_builds(), 2u);
  live.set_entity_pose(robot, moved);  // the same pose: nothing to rebuild
  live.advance(0.15, sink);  // tick 2
  EXPECT_EQ(live.scene_builds(), 2u);
  ASSERT_EQ(ticks.size(), 6u);
  for (const TickReadings& t : ticks) {
    if (t.antenna != 0) continue;
    EXPECT_EQ(t.antenna_pose.position, mast_pose.position);
  }
  EXPECT_EQ(ticks[1].antenna_pose.position, live.scenario().antennas[1].motion.pose.position);
}

// The bridge on a script, without listeners: its exit status and log.
struct BridgeRun {
  int bridge = -1, gazebo = -1;
  std::string log;
};
BridgeRun run_bridge(const fs::path& dir, const ScriptOptions& script, std::vector<std::string> extra_args) {
  write_script(dir / "script.txt", script);
  std::vector<std::string> args = {"gazebo", "--input", "ros", "--world", kRosDir + "/paper_robot.world", "--frame",
                                   "mobile=mast_link", "--seed", std::to_string(kRosSeed), "--csv",
                                   (dir / "bridge").string(), "--idle-timeout", "20"};
  if (std::find(extra_args.begin(), extra_args.end(), "--no-sim-time") == extra_args.end())
    args.push_back("--sim-time");
  args.insert(args.end(), extra_args.begin(), extra_args.end());
  BridgeRun r;
  BridgeProcess bridge(args, dir / "bridge.log");
  Child gazebo({RFIDRAY_FAKE_GAZEBO11, (dir / "script.txt").string(), "30"}, dir / "fake_gazebo11.log");
  r.bridge = bridge.wait(30000ms);
  r.gazebo = gazebo.wait(30000ms);
  r.log = slurp(dir / "bridge.log");
  return r;
}

TEST(RosInputErrors, ModelNotInTheWorldIsAnErrorUnlessIgnored) {
  if (!have_rosmaster()) GTEST_SKIP() << "rosmaster not installed (Debian package python3-rosmaster)";
  RosMaster ros("ros_unknown_model");
  ASSERT_TRUE(ros.up());
  // No --duration here: the bridge would stop when the clock reaches it, and /clock and /gazebo/model_states come on
  // separate connections, so it could get there before it has read one model_states (flaky). It stops at the first
  // model_states now (or, were there none, after --idle-timeout with status 0: a failure, not a flake).
  const BridgeRun bad = run_bridge(ros.dir, {tick_times(0, 10), true, "forklift"}, {"--connect-timeout", "0"});
  EXPECT_EQ(bad.bridge, 2) << bad.log;
  EXPECT_NE(bad.log.find("/gazebo/model_states: model 'forklift' is not in world 'paper_robot'"), std::string::npos)
      << bad.log;
  EXPECT_NE(bad.log.find("--ignore-model forklift"), std::string::npos) << bad.log;
  const BridgeRun ok = run_bridge(ros.dir, {tick_times(0, 10), true, "forklift"},
                                  {"--duration", "0.5", "--ignore-model", "forklift", "--connect-timeout", "0"});
  EXPECT_EQ(ok.bridge, 0) << ok.log;
  EXPECT_NE(ok.log.find("16 antenna ticks"), std::string::npos) << ok.log;  // 8 ticks (k / 15 <= 0.5) each
}

TEST(RosInputErrors, TfChainThatNeverResolvesIsAnErrorNamingIt) {
  if (!have_rosmaster()) GTEST_SKIP() << "rosmaster not installed (Debian package python3-rosmaster)";
  RosMaster ros("ros_no_tf");
  ASSERT_TRUE(ros.up());
  // Nobody publishes base_link -> mast_link.
  const BridgeRun r = run_bridge(ros.dir, {tick_times(0, 10), false, ""}, {"--duration", "0.5", "--tf-timeout", "1", "--connect-timeout", "0"});
  EXPECT_EQ(r.bridge, 2) << r.log;
  EXPECT_NE(r.log.find("TF: no transform world -> mast_link (antenna 'mobile') at t = 0 s within 1 s"),
            std::string::npos) << r.log;
  EXPECT_NE(r.log.find("frames known: "), std::string::npos) << r.log;
}

TEST(RosInputTime, WithoutSimTimeTheTfStampsAreTheTime) {
  if (!have_rosmaster()) GTEST_SKIP() << "rosmaster not installed (Debian package python3-rosmaster)";
  RosMaster ros("ros_tf_time");
  ASSERT_TRUE(ros.up());
  // No /clock: ticks 0 … 7 (k / 15 <= 0.5) come as the /tf stamps pass them.
  ScriptOptions script{tick_times(0, 8)};
  script.clock = false;
  const BridgeRun r = run_bridge(ros.dir, script, {"--duration", "0.5", "--no-sim-time", "--connect-timeout", "0"});
  ASSERT_EQ(r.bridge, 0) << r.log;
  EXPECT_NE(r.log.find("time from /tf stamps"), std::string::npos) << r.log;
  EXPECT_NE(r.log.find("16 antenna ticks"), std::string::npos) << r.log;
  ASSERT_EQ(run_simulate(ros.dir, "0.5"), 0) << slurp(ros.dir / "simulate.log");
  for (const std::string antenna : {"mobile", "fixed"})
    EXPECT_EQ(slurp(ros.dir / "bridge" / (antenna + ".csv")), slurp(ros.dir / "sim" / (antenna + ".csv"))) << antenna;
}

TEST(RosInputErrors, TimeGoingBackRestartsTheTicks) {
  if (!have_rosmaster()) GTEST_SKIP() << "rosmaster not installed (Debian package python3-rosmaster)";
  RosMaster ros("ros_reset");
  ASSERT_TRUE(ros.up());
  // Gazebo runs to 2 s, is reset, and runs again past 2 s: ticks 0 … 29 (before 2 s), then 0 … 30 again.
  // The reset waits until the bridge has published ticks 0 … 29 (its TF buffer then starts over).
  std::vector<double> times = tick_times(0, 30);
  for (double t : tick_times(0, 31)) times.push_back(t);
  const BridgeRun r = run_bridge(ros.dir, {times, true, "", 31, 30}, {"--duration", "2", "--connect-timeout", "15"});
  ASSERT_EQ(r.bridge, 0) << r.log;
  EXPECT_NE(r.log.find("simulation time went back to 0 s (a reset): ticks start again from there"), std::string::npos)
      << r.log;
  EXPECT_NE(r.log.find("1 resets"), std::string::npos) << r.log;
  ASSERT_EQ(run_simulate(ros.dir, "2"), 0) << slurp(ros.dir / "simulate.log");
  // The same motion again after the reset: the same rows, by the same (seed, antenna, tick) random streams.
  for (const std::string antenna : {"mobile", "fixed"}) {
    std::istringstream sim(slurp(ros.dir / "sim" / (antenna + ".csv")));
    std::string header, line, before_reset, all;
    std::getline(sim, header);
    while (std::getline(sim, line)) {
      if (line.rfind("2.000000,", 0) != 0) before_reset += line + "\n";
      all += line + "\n";
    }
    EXPECT_FALSE(before_reset.empty());
    EXPECT_EQ(slurp(ros.dir / "bridge" / (antenna + ".csv")), header + "\n" + before_reset + all) << antenna;
  }
}

}  // namespace
}  // namespace rfidray::gazebo
