// Soak test of the live bridge (`rfidray gazebo` over ign-transport on loopback): 3 s of simulation time with
// poses at 1 kHz, the robot (antenna "reader") and the crate (an obstacle in the traced scene) moving on every
// message, malformed poses mixed in (NaN, inf, beyond the coordinate range, zero quaternions, unknown ids), and
// Gazebo's publisher going away and coming back twice. The bridge must neither crash nor leak (the sanitizer
// build runs it with LeakSanitizer: a leak is a non-zero exit), must drop exactly the malformed poses, and
// must account for every tick: /rfid/status's tick count = TagReadings messages received = rows of ticks in
// the CSV = duration × rate + 1 per antenna, with every value finite.
#include <gtest/gtest.h>

#include <cmath>
#include <mutex>
#include <optional>

#include "adapters/gazebo/msgs/rfid_readings.pb.h"
#include "io/readings_csv.h"
#include "tests/adapters/gazebo/fake_gazebo.h"

namespace rfidray::gazebo {
namespace {

using namespace fake;

// What message k (1 ms of simulation time each) sends: both poses move, and some messages carry a malformed
// pose for one of them. Returns how many malformed poses of known entities it carries.
int soak_message(const GazeboWorld& w, int k, ignition::msgs::Pose_V& v) {
  const int64_t stamp_ns = static_cast<int64_t>(k) * 1000000;
  v.Clear();
  v.mutable_header()->mutable_stamp()->set_sec(stamp_ns / 1000000000);
  v.mutable_header()->mutable_stamp()->set_nsec(static_cast<int32_t>(stamp_ns % 1000000000));
  const double t = 1e-3 * k;
  const Pose robot{Vec3(0.3 * t, -0.2 * t, 0.0), Quat(Eigen::AngleAxisd(0.4 * t, Vec3::UnitZ()))};
  const Pose crate{Vec3(-2.0 + 1.0 * t, 3.0, 0.5), Quat(Eigen::AngleAxisd(0.2 * t, Vec3::UnitZ()))};
  int malformed = 0;
  for (const auto& [name, pose] : {std::pair{"robot", robot}, {"crate", crate}}) {
    auto* p = v.add_pose();
    p->set_name(name);
    p->set_id(w.find(name) + 1);
    to_msg(pose, *p);
    const bool is_robot = std::string(name) == "robot";
    if (is_robot && k % 97 == 0) {
      p->mutable_position()->set_x(std::nan(""));
      ++malformed;
    } else if (!is_robot && k % 101 == 0) {
      p->mutable_position()->set_y(1e308);
      ++malformed;
    } else if (is_robot && k % 89 == 0) {
      p->mutable_orientation()->set_w(0.0), p->mutable_orientation()->set_x(0.0);
      p->mutable_orientation()->set_y(0.0), p->mutable_orientation()->set_z(0.0);
      ++malformed;
    } else if (!is_robot && k % 83 == 0) {
      p->mutable_orientation()->set_z(std::numeric_limits<double>::infinity());
      ++malformed;
    }
  }
  if (k % 7 == 0) {  // an entity the bridge does not know, with garbage: ignored, not counted
    auto* p = v.add_pose();
    p->set_name("visual");
    p->set_id(999999);
    p->mutable_position()->set_z(std::nan(""));
  }
  return malformed;
}

TEST(BridgeSoak, ThousandHertzPosesWithMalformedOnesAndAReconnectingPublisher) {
  const std::string partition = private_partition();
  const fs::path dir = fs::temp_directory_path() / partition;
  fs::create_directories(dir);
  GazeboWorld world = load_world(world_options());
  FakeGazebo gazebo(world);
  ASSERT_TRUE(gazebo.advertised);

  std::mutex mutex;
  std::map<std::string, uint64_t> received;
  bool non_finite = false;
  std::optional<rfidray::msgs::BridgeStatus> last_status;
  std::atomic<uint64_t> status_poses{0};
  std::function<void(const rfidray::msgs::TagReadings&)> on_readings = [&](const rfidray::msgs::TagReadings& m) {
    std::lock_guard<std::mutex> lock(mutex);
    ++received[m.antenna()];
    for (const auto& tag : m.tags())
      non_finite |= !std::isfinite(tag.phase_rad()) || !std::isfinite(tag.rssi()) || !std::isfinite(tag.dist());
  };
  std::function<void(const rfidray::msgs::BridgeStatus&)> on_status = [&](const rfidray::msgs::BridgeStatus& m) {
    std::lock_guard<std::mutex> lock(mutex);
    if (!last_status || m.pose_messages() >= last_status->pose_messages()) last_status = m;
    status_poses = m.pose_messages();
  };
  ASSERT_TRUE(gazebo.node.Subscribe("/rfid/reader/readings", on_readings));
  ASSERT_TRUE(gazebo.node.Subscribe("/rfid/gate/readings", on_readings));
  ASSERT_TRUE(gazebo.node.Subscribe("/rfid/status", on_status));

  constexpr double kSoakDuration = 3.0;
  BridgeProcess bridge({"gazebo", "--world", world_options().file, "--resource-path", kDir + "/models", "--seed",
                        std::to_string(kSeed), "--channel", "los+blocked", "--duration", "3", "--csv", dir.string(),
                        "--idle-timeout", "30", "--connect-timeout", "10", "--scene-timeout", "20"},
                       dir / "bridge.log");
  ASSERT_TRUE(bridge.running());
  // The t = 0 state until the bridge answers (discovery can drop the first messages).
  const auto until = std::chrono::steady_clock::now() + 20s;
  ignition::msgs::Pose_V v;
  while (status_poses == 0 && std::chrono::steady_clock::now() < until && bridge.running()) {
    soak_message(world, 0, v);
    gazebo.poses.Publish(v);
    std::this_thread::sleep_for(50ms);
  }
  ASSERT_GT(status_poses.load(), 0u) << slurp(dir / "bridge.log");

  // 1 kHz of simulation time, about 2 kHz of wall time. Gazebo's publisher leaves at 1.0 s and 2.0 s of
  // simulation time and comes back 300 ms (wall) later; what it sent meanwhile is lost, which the bridge must
  // survive (ticks follow the stamps, not the message count).
  const int last_k = static_cast<int>(kSoakDuration * 1000) + 200;
  for (int k = 1; k <= last_k && bridge.running(); ++k) {
    if (k == 1000 || k == 2000) {
      gazebo.poses = ignition::transport::Node::Publisher();  // unadvertises
      std::this_thread::sleep_for(300ms);
      gazebo.poses = gazebo.node.Advertise<ignition::msgs::Pose_V>("/world/rfid_test/dynamic_pose/info");
      ASSERT_TRUE(gazebo.poses.Valid());
      // Wait until the bridge has heard from the new publisher before going on (bounded).
      const uint64_t before = status_poses;
      const auto reconnect_until = std::chrono::steady_clock::now() + 10s;
      while (status_poses == before && std::chrono::steady_clock::now() < reconnect_until) {
        soak_message(world, k, v);
        gazebo.poses.Publish(v);
        std::this_thread::sleep_for(20ms);
      }
    }
    soak_message(world, k, v);
    gazebo.poses.Publish(v);
    if (k % 2 == 0) std::this_thread::sleep_for(1ms);
  }
  ASSERT_EQ(bridge.wait(30000ms), 0) << "bridge log:\n" << slurp(dir / "bridge.log");
  const std::string log = slurp(dir / "bridge.log");
  std::printf("bridge log:\n%s", log.c_str());

  Scenario s = world.scenario;
  std::lock_guard<std::mutex> lock(mutex);
  ASSERT_TRUE(last_status.has_value());
  uint64_t expected_ticks = 0;
  for (const AntennaSpec& a : s.antennas) {
    const std::string& name = a.reader.name;
    const uint64_t ticks = static_cast<uint64_t>(kSoakDuration * a.reader.update_rate_hz + 1e-9) + 1;
    expected_ticks += ticks;
    EXPECT_EQ(received[name], ticks) << "antenna " << name;
    // The CSV: one row per read, every tick time within the run, every value finite.
    const std::vector<io::ReadingRow> rows = io::read_readings_csv(dir / (name + ".csv"));
    EXPECT_FALSE(rows.empty()) << name;
    for (const io::ReadingRow& r : rows) {
      EXPECT_TRUE(r.antenna_pose.position.allFinite());
      EXPECT_LE(r.time_s, kSoakDuration + 1e-9);
    }
  }
  EXPECT_FALSE(non_finite);
  EXPECT_EQ(last_status->ticks(), expected_ticks);
  EXPECT_GT(last_status->rejected_poses(), 0u);
  EXPECT_NE(log.find("dropped a malformed pose"), std::string::npos);
  EXPECT_NE(log.find(std::to_string(last_status->rejected_poses()) + " malformed poses dropped"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rfidray::gazebo
