// The ROS 1 pose input end to end, with a ROS master of its own: a fake Gazebo 11 (fake_gazebo11.cpp, its
// own process) plays the paper's robot driving its L path — /gazebo/model_states, /tf (odom → base_link →
// mast_link, the mast sliding up and down), /tf_static (world → odom) and /clock — and `rfidray gazebo
// --input ros` follows it on paper_robot.world, whose antenna block is the seed plugin's, unchanged. Plain
// roscpp subscribers receive every TagArray on the seed's topics, and the bridge's readings CSV equals
// `rfidray simulate paper_robot.yaml` (the same motion) byte for byte.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <algorithm>
#include <cstdio>

#include "core/mast.h"
#include "io/scenario_yaml.h"
#include "tests/adapters/gazebo/fake_gazebo.h"

namespace rfidray::gazebo {
namespace {

using namespace fake;
const std::string kRosDir = std::string(RFIDRAY_SOURCE_DIR) + "/tests/adapters/ros";
constexpr double kRate = 15.0;  // both antennas; the run: 23 s (the robot stops at 23.57 s)
constexpr int kTicks = 346;     // k / 15 <= 23
constexpr uint64_t kRosSeed = 11;

struct Child : ChildProcess {
  Child(std::vector<std::string> argv, const fs::path& log) : ChildProcess(std::move(argv), log, SIGTERM) {}
};

bool port_open(int port) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(port));
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const bool ok = connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  close(fd);
  return ok;
}

void put_pose(std::FILE* f, const Pose& p) {
  std::fprintf(f, " %.17g %.17g %.17g %.17g %.17g %.17g %.17g", p.position.x(), p.position.y(), p.position.z(),
               p.orientation.x(), p.orientation.y(), p.orientation.z(), p.orientation.w());
}

// What Gazebo 11 and the robot's TF publishers send, one step per tick time k / 15 s (one past the end, so
// the clock passes the last tick).
void write_script(const fs::path& path) {
  const Scenario s = io::load_scenario(kRosDir + "/paper_robot.yaml");
  const SceneMotion motion = build_motion(s);
  const MastParams mast = *s.antennas[0].motion.mast;
  WorldOptions wo;
  wo.file = kRosDir + "/paper_robot.world";
  const GazeboWorld world = load_world(wo);
  std::FILE* f = std::fopen(path.c_str(), "w");
  ASSERT_NE(f, nullptr);
  std::fprintf(f, "static world odom");
  put_pose(f, Pose{});
  std::fprintf(f, "\n");
  for (int k = 0; k <= kTicks; ++k) {
    const double t = static_cast<double>(k) / kRate;
    const Pose robot = motion.robots[0]->pose_at(t);
    std::fprintf(f, "step %.17g\ntf odom base_link", t);
    put_pose(f, robot);
    std::fprintf(f, "\ntf base_link mast_link");
    put_pose(f, Pose{Vec3(0, 0, mast_height_m(mast, t)), Quat::Identity()});
    std::fprintf(f, "\n");
    for (const Entity& e : world.entities) {
      if (e.parent >= 0 || e.kind != Entity::Kind::kModel) continue;
      std::fprintf(f, "model %s", e.name.c_str());
      put_pose(f, e.name == "p3at" ? robot : e.pose);
      std::fprintf(f, "\n");
    }
  }
  std::fclose(f);
}

struct RosMaster {
  fs::path dir;
  std::unique_ptr<Child> master;
  int port = 0;
  explicit RosMaster(const std::string& name) {
    dir = fs::temp_directory_path() / (name + "_" + std::to_string(getpid()));
    fs::remove_all(dir);
    fs::create_directories(dir);
    port = 20000 + static_cast<int>((getpid() * 7 + 3) % 20000);  // clear of 11311 and of the other test's
    const std::string uri = "http://127.0.0.1:" + std::to_string(port);
    ::setenv("ROS_MASTER_URI", uri.c_str(), 1);
    ::setenv("ROS_IP", "127.0.0.1", 1);
    ::setenv("ROS_HOME", dir.c_str(), 1);
    master = std::make_unique<Child>(std::vector<std::string>{RFIDRAY_ROSMASTER, "--core", "-p", std::to_string(port)},
                                     dir / "rosmaster.log");
    const auto until = std::chrono::steady_clock::now() + 15s;
    while (!port_open(port) && std::chrono::steady_clock::now() < until) std::this_thread::sleep_for(20ms);
  }
  bool up() const { return port_open(port); }
};

int run_simulate(const fs::path& dir) {
  BridgeProcess sim({"simulate", kRosDir + "/paper_robot.yaml", "--seed", std::to_string(kRosSeed), "--duration",
                     "23", "-o", (dir / "sim").string(), "-q"},
                    dir / "simulate.log");
  return sim.wait(60000ms);
}

bool have_rosmaster() {
  const std::string m = RFIDRAY_ROSMASTER;
  return !m.empty() && m.find("NOTFOUND") == std::string::npos;
}

TEST(RosInputEndToEnd, Gazebo11RobotOnTheLPathGivesTheReadingsOfSimulate) {
  if (!have_rosmaster()) GTEST_SKIP() << "rosmaster not installed (Debian package python3-rosmaster)";
  RosMaster ros("rfidray_ros_input");
  ASSERT_TRUE(ros.up()) << slurp(ros.dir / "rosmaster.log");
  const fs::path& dir = ros.dir;
  write_script(dir / "script.txt");

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
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rfidray::gazebo
