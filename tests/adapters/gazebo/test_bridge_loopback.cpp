// `rfidray gazebo` over real ign-transport on loopback: this test plays Gazebo (the scene/info service and
// Pose_V on dynamic_pose/info) in a partition of its own; the bridge runs as a separate process, moves the
// robot's antenna and the crate, and publishes readings. They must arrive, and equal `simulate` for the same
// poses and seed, tick by tick: its CSV byte for byte, its TagReadings value for value.
#include <gtest/gtest.h>

#include <mutex>
#include <optional>

#include "adapters/gazebo/msgs/rfid_readings.pb.h"
#include "io/readings_csv.h"
#include "tests/adapters/gazebo/fake_gazebo.h"

namespace rfidray::gazebo {
namespace {

using namespace fake;

TEST(BridgeLoopback, ReadingsArriveAndMatchSimulate) {
  const std::string partition = private_partition();
  const fs::path dir = fs::temp_directory_path() / partition;
  fs::create_directories(dir);
  GazeboWorld world = load_world(world_options());
  FakeGazebo gazebo(world);
  ASSERT_TRUE(gazebo.advertised);

  std::mutex mutex;
  std::map<std::string, std::vector<rfidray::msgs::TagReadings>> received;
  std::atomic<uint64_t> status_poses{0};
  std::function<void(const rfidray::msgs::TagReadings&)> on_readings = [&](const rfidray::msgs::TagReadings& m) {
    std::lock_guard<std::mutex> lock(mutex);
    received[m.antenna()].push_back(m);
  };
  std::function<void(const rfidray::msgs::BridgeStatus&)> on_status = [&](const rfidray::msgs::BridgeStatus& m) {
    status_poses = m.pose_messages();
  };
  ASSERT_TRUE(gazebo.node.Subscribe("/rfid/reader/readings", on_readings));
  ASSERT_TRUE(gazebo.node.Subscribe("/rfid/gate/readings", on_readings));
  ASSERT_TRUE(gazebo.node.Subscribe("/rfid/status", on_status));

  BridgeProcess bridge({"gazebo", "--world", world_options().file, "--resource-path", kDir + "/models", "--seed",
                        std::to_string(kSeed), "--channel", "los+blocked", "--duration", "2", "--csv", dir.string(),
                        "--idle-timeout", "20", "--connect-timeout", "10", "--scene-timeout", "20"},
                       dir / "bridge.log");
  ASSERT_TRUE(bridge.running());

  ASSERT_TRUE(play(world, gazebo.poses, status_poses, bridge))
      << "the bridge never acknowledged a pose message; its log:\n" << slurp(dir / "bridge.log");
  ASSERT_EQ(bridge.wait(20000ms), 0) << "bridge log:\n" << slurp(dir / "bridge.log");
  std::printf("bridge log:\n%s", slurp(dir / "bridge.log").c_str());  // what a user sees (ctest -V)

  // The reference: simulate() in each state; ticks before the switch from the first, after from the second.
  Scenario s1, s2;
  const SimulationResult r1 = simulate_state(false, s1), r2 = simulate_state(true, s2);
  for (size_t a = 0; a < s1.antennas.size(); ++a) {
    const std::string& name = s1.antennas[a].reader.name;
    std::vector<ReadRecord> expected;
    for (const ReadRecord& r : r1.antennas[a].reads)
      if (r.time_s < kSwitch) expected.push_back(r);
    for (const ReadRecord& r : r2.antennas[a].reads)
      if (r.time_s >= kSwitch) expected.push_back(r);
    ASSERT_FALSE(expected.empty());
    std::ostringstream csv;
    csv << io::kReadingsHeader << '\n';
    io::write_readings_rows(csv, s1, a, expected);
    EXPECT_EQ(slurp(dir / (name + ".csv")), csv.str()) << "antenna " << name;

    // Every tick arrived on ign-transport (the bridge waited for this subscriber), with the same values.
    std::lock_guard<std::mutex> lock(mutex);
    const auto& msgs = received[name];
    const uint64_t ticks = static_cast<uint64_t>(kDuration * s1.antennas[a].reader.update_rate_hz + 1e-9) + 1;
    ASSERT_EQ(msgs.size(), ticks) << "antenna " << name;
    size_t k = 0;
    for (const auto& m : msgs) {
      for (const auto& tag : m.tags()) {
        ASSERT_LT(k, expected.size());
        const ReadRecord& e = expected[k++];
        EXPECT_EQ(m.tick(), e.tick);
        EXPECT_EQ(tag.name(), s1.tags[e.tag].tag.name);
        EXPECT_EQ(tag.phase_rad(), e.reading.phase_rad);
        EXPECT_EQ(tag.rssi(), e.reading.rssi_dbm);
        EXPECT_EQ(tag.dist(), e.distance_m);
      }
    }
    EXPECT_EQ(k, expected.size()) << "antenna " << name;
  }
  // The moves mattered: the reader's distance to tag_1 and the gate's RSSI of tag_2 (crate in the way) change.
  // (the crate either silences tag_2 or costs it more than 1 dB).
  auto rssi_of = [](const SimulationResult& r, size_t antenna, uint32_t tag) -> std::optional<double> {
    for (const ReadRecord& rec : r.antennas[antenna].reads)
      if (rec.tag == tag) return rec.reading.rssi_dbm;
    return std::nullopt;
  };
  ASSERT_TRUE(rssi_of(r1, 1, 1).has_value());
  EXPECT_TRUE(!rssi_of(r2, 1, 1) || *rssi_of(r2, 1, 1) < *rssi_of(r1, 1, 1) - 1.0);
  EXPECT_NE(r1.antennas[0].reads[0].distance_m, r2.antennas[0].reads[0].distance_m);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rfidray::gazebo
