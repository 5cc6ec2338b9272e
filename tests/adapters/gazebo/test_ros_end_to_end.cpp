// End to end through ROS 1: a ROS master (rosmaster, on a port of our own), an ordinary roscpp subscriber of
// rfid_sensor/TagArray in its own process (tests/ros/tag_array_listener.cpp), `rfidray gazebo --ros`, and this
// test playing Gazebo over ign-transport. Every antenna tick arrives on /gazebo/reader/data as the seed plugin
// fills it, with the values of simulate() for the same poses and seed.
#include <gtest/gtest.h>

#include <cmath>

#include "tests/adapters/gazebo/fake_gazebo.h"
#ifdef RFIDRAY_HAVE_ROS_TEST
#include "tests/support/ros_master.h"
#endif

namespace rfidray::gazebo {
namespace {

using namespace fake;

#ifdef RFIDRAY_HAVE_ROS_TEST
using Child = rfidray::testing::RosChild;
#endif

TEST(RosEndToEnd, SubscriberReceivesTagArray) {
#ifndef RFIDRAY_HAVE_ROS_TEST
  GTEST_SKIP() << "built without roscpp/gencpp";
#else
  if (!rfidray::testing::have_rosmaster())
    GTEST_SKIP() << "rosmaster not installed (Debian package python3-rosmaster)";
  const auto t0 = std::chrono::steady_clock::now();
  auto mark = [&](const char* what) {
    std::fprintf(stderr, "[%.3f s] %s\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(), what);
  };
  private_partition();
  // A master of our own on loopback: a port from our pid, clear of 11311.
  const rfidray::testing::RosMaster ros("ros_end_to_end", 20000 + static_cast<int>(getpid() % 20000));
  const fs::path& dir = ros.dir;
  ASSERT_TRUE(ros.up()) << "rosmaster did not come up on port " << ros.port() << ":\n" << slurp(dir / "rosmaster.log");

  mark("master up");
  GazeboWorld world = load_world(world_options());
  FakeGazebo gazebo(world);
  ASSERT_TRUE(gazebo.advertised);
  std::atomic<uint64_t> status_poses{0};
  std::function<void(const rfidray::msgs::BridgeStatus&)> on_status = [&](const rfidray::msgs::BridgeStatus& m) {
    status_poses = m.pose_messages();
  };
  ASSERT_TRUE(gazebo.node.Subscribe("/rfid/status", on_status));
  // The bridge waits for a subscriber on each of its outputs, ign-transport ones included.
  std::function<void(const rfidray::msgs::TagReadings&)> ignore = [](const rfidray::msgs::TagReadings&) {};
  ASSERT_TRUE(gazebo.node.Subscribe("/rfid/reader/readings", ignore));
  ASSERT_TRUE(gazebo.node.Subscribe("/rfid/gate/readings", ignore));

  const int ticks = 21;  // reader: 10 Hz over [0, 2] s
  Child listener({RFIDRAY_TAG_ARRAY_LISTENER, "/gazebo/reader/data", std::to_string(ticks), "30",
                  (dir / "tag_array.txt").string()},
                 dir / "listener.log");
  Child gate_listener({RFIDRAY_TAG_ARRAY_LISTENER, "/gazebo/gate/data", "11", "30", (dir / "gate.txt").string()},
                      dir / "gate_listener.log");
  // The bridge waits (--connect-timeout) for a subscriber on every topic, so the first TagArray is not lost.
  BridgeProcess bridge({"gazebo", "--world", world_options().file, "--resource-path", kDir + "/models", "--seed",
                        std::to_string(kSeed), "--channel", "los+blocked", "--duration", "2", "--ros",
                        "--idle-timeout", "20", "--connect-timeout", "15", "--scene-timeout", "20"},
                       dir / "bridge.log");
  ASSERT_TRUE(play(world, gazebo.poses, status_poses, bridge)) << "bridge log:\n" << slurp(dir / "bridge.log");
  mark("played");
  ASSERT_EQ(bridge.wait(20000ms), 0) << "bridge log:\n" << slurp(dir / "bridge.log");
  mark("bridge done");
  ASSERT_EQ(gate_listener.wait(20000ms), 0) << "gate listener:\n" << slurp(dir / "gate_listener.log");
  ASSERT_EQ(listener.wait(20000ms), 0) << "listener:\n" << slurp(dir / "listener.log") << "bridge:\n"
                                       << slurp(dir / "bridge.log");

  mark("listeners done");
  Scenario s1, s2;
  const SimulationResult r1 = simulate_state(false, s1), r2 = simulate_state(true, s2);
  std::istringstream in(slurp(dir / "tag_array.txt"));
  std::string line;
  int k = 0;
  while (std::getline(in, line)) {
    std::istringstream f(line);
    double stamp, px, py, pz, qx, qy, qz, qw;
    unsigned ntags;
    std::string frame;
    f >> stamp >> ntags >> px >> py >> pz >> qx >> qy >> qz >> qw >> frame;
    EXPECT_EQ(frame, "world");
    EXPECT_DOUBLE_EQ(stamp, k / 10.0);
    const bool second = k / 10.0 >= kSwitch;
    const SimulationResult& r = second ? r2 : r1;
    std::vector<ReadRecord> expected;
    for (const ReadRecord& rec : r.antennas[0].reads)
      if (rec.tick == static_cast<uint64_t>(k)) expected.push_back(rec);
    ASSERT_EQ(ntags, expected.size()) << "tick " << k;
    const Vec3 pos = (second ? s2 : s1).antennas[0].motion.pose.position;
    EXPECT_NEAR(px, pos.x(), 1e-12);
    EXPECT_NEAR(py, pos.y(), 1e-12);
    EXPECT_NEAR(pz, pos.z(), 1e-12);
    for (const ReadRecord& e : expected) {
      std::string name;
      double dist, phi, rssi;
      f >> name >> dist >> phi >> rssi;
      EXPECT_EQ(name, s1.tags[e.tag].tag.name);
      EXPECT_EQ(dist, e.distance_m);
      EXPECT_EQ(phi, std::remainder(e.reading.phase_rad, 2.0 * kPi));  // the seed's (−π, π]
      EXPECT_EQ(rssi, e.reading.rssi_dbm);
    }
    ++k;
  }
  EXPECT_EQ(k, ticks);
#endif
}

}  // namespace
}  // namespace rfidray::gazebo
