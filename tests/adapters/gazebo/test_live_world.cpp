// LiveWorld without transport: when ticks are computed (the poses held at or before each tick), in what
// order, from which first message, what a move changes, and a reset of simulation time.
#include <gtest/gtest.h>

#include "adapters/gazebo/live_world.h"

namespace rfidray::gazebo {
namespace {

const std::string kDir = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/tests/gazebo";

GazeboWorld test_world() {
  WorldOptions o;
  o.file = kDir + "/rfid_test.world";
  o.resource_path = {kDir + "/models"};
  return load_world(o);
}

ignition::msgs::Pose_V robot_at(double x) {
  ignition::msgs::Pose_V v;
  auto* p = v.add_pose();
  p->set_name("robot");  // no scene/info map: matched by its unique name
  p->mutable_position()->set_x(x);
  p->mutable_orientation()->set_w(1.0);
  return v;
}

TEST(LiveWorld, TicksUseThePosesHeldAtTheirTime) {
  LiveWorld live(test_world(), {});  // reader 10 Hz (antenna 0), gate 5 Hz (antenna 1)
  std::vector<TickReadings> out;
  auto sink = [&](const TickReadings& t) { out.push_back(t); };
  EXPECT_EQ(live.apply(0.05, robot_at(0.0), sink), 0u);  // starts: first ticks at 0.1 (reader) and 0.2 (gate)
  EXPECT_EQ(live.apply(0.35, robot_at(1.0), sink), 4u);  // reader 0.1, 0.2, 0.3 and gate 0.2, with x = 0
  EXPECT_EQ(live.apply(0.45, robot_at(1.0), sink), 2u);  // reader 0.4 and gate 0.4 with x = 1
  ASSERT_EQ(out.size(), 6u);
  const std::vector<std::pair<size_t, uint64_t>> order = {{0, 1}, {0, 2}, {1, 1}, {0, 3}, {0, 4}, {1, 2}};
  for (size_t i = 0; i < out.size(); ++i) {
    EXPECT_EQ(out[i].antenna, order[i].first) << i;
    EXPECT_EQ(out[i].tick, order[i].second) << i;
  }
  EXPECT_DOUBLE_EQ(out[3].antenna_pose.position.x(), 0.0);  // reader 0.3: before the move at 0.35
  EXPECT_DOUBLE_EQ(out[4].antenna_pose.position.x(), 1.0);  // reader 0.4: after
  EXPECT_DOUBLE_EQ(out[4].antenna_pose.position.z(), 1.5);  // the sensor's pose on its link
  // The reading is the one simulate() makes for that pose, tick and seed.
  const std::vector<Pose> tags = {live.scenario().tags[0].motion.pose, live.scenario().tags[1].motion.pose};
  const std::vector<size_t> present = {0, 1};
  const auto expected = simulate_tick(live.scenario(), IdealChannel(), 0, 4, out[4].antenna_pose, tags, present);
  ASSERT_EQ(out[4].reads.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(out[4].reads[i].reading.phase_rad, expected[i].reading.phase_rad);
  EXPECT_NEAR(out[4].reads[0].distance_m, 2.0, 1e-12);  // tag_1 at (3, 0, 1.5)
}

TEST(LiveWorld, DurationAndReset) {
  LiveOptions o;
  o.duration_s = 0.3;
  LiveWorld live(test_world(), o);
  std::vector<TickReadings> out;
  auto sink = [&](const TickReadings& t) { out.push_back(t); };
  live.apply(0.0, robot_at(0.0), sink);
  live.apply(5.0, robot_at(0.0), sink);
  EXPECT_EQ(out.size(), 4u + 2u);  // reader 0, 0.1, 0.2, 0.3; gate 0, 0.2 — nothing after 0.3
  EXPECT_TRUE(live.finished());

  LiveWorld again(test_world(), {});
  out.clear();
  again.apply(2.0, robot_at(0.0), sink);
  again.apply(2.25, robot_at(0.0), sink);  // reader 2.0, 2.1, 2.2; gate 2.0, 2.2
  EXPECT_EQ(out.size(), 5u);
  again.apply(0.5, robot_at(0.0), sink);  // reset to 0.5
  out.clear();
  again.apply(0.65, robot_at(0.0), sink);  // reader 0.5, 0.6; gate 0.6
  ASSERT_EQ(out.size(), 3u);
  EXPECT_EQ(out[0].tick, 5u);
}

}  // namespace
}  // namespace rfidray::gazebo
