#pragma once
// Test helpers playing Gazebo for the bridge tests: the scene/info reply and Pose_V messages of
// scenes/tests/gazebo/rfid_test.world in two states, the bridge as a child process, and simulate() on the
// same states as the reference. The child processes are tests/support/child_process.h's.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <ignition/msgs/empty.pb.h>
#include <ignition/msgs/pose_v.pb.h>
#include <ignition/msgs/scene.pb.h>
#include <ignition/transport/Node.hh>
#include <map>
#include <sstream>
#include <thread>

#include "raytrace/channel_factory.h"
#include "adapters/gazebo/entity_map.h"
#include "adapters/gazebo/gazebo_world.h"
#include "adapters/gazebo/msgs/rfid_readings.pb.h"
#include "io/world_source.h"
#include "core/simulation.h"
#include "core/units.h"
#include "tests/support/child_process.h"
#include "tests/support/files.h"

namespace rfidray::gazebo::fake {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
const std::string kDir = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/tests/gazebo";
constexpr uint64_t kSeed = 7;
constexpr double kDuration = 2.0, kSwitch = 0.975;  // poses change between ticks (reader 10 Hz, gate 5 Hz)

inline WorldOptions world_options() {
  WorldOptions o;
  o.file = kDir + "/rfid_test.world";
  o.resource_path = {kDir + "/models"};
  return o;
}

// The two states Gazebo goes through: the robot (antenna "reader") drives and turns, and the crate is
// moved between the gate antenna and tag_2 (so the traced channel changes too).
inline Pose robot_pose(bool second) {
  return second ? Pose{Vec3(1.0, -1.0, 0.0), Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()))} : Pose{};
}
inline Pose crate_pose(bool second) {
  // Turned 90°: x in [0.5, 2.5], y in [2.5, 3.5], z in [1, 2]; the gate–tag_2 line crosses its faces y = 3.5, 2.5.
  return second ? Pose{Vec3(1.5, 3.0, 1.5), Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()))}
                : Pose{Vec3(-2, 3, 0.5), Quat::Identity()};
}

// Gazebo's ids for our entities: index + 1; sensors 1000 + mount.
inline ignition::msgs::Scene scene_of(const GazeboWorld& w) {
  ignition::msgs::Scene scene;
  scene.set_name(w.name);
  std::map<int, ignition::msgs::Model*> models;
  for (size_t e = 0; e < w.entities.size(); ++e) {
    const Entity& ent = w.entities[e];
    if (ent.kind == Entity::Kind::kModel) {
      ignition::msgs::Model* m = ent.parent < 0 ? scene.add_model() : models.at(ent.parent)->add_model();
      m->set_name(ent.name);
      m->set_id(e + 1);
      to_msg(ent.pose, *m->mutable_pose());
      models[static_cast<int>(e)] = m;
    } else {
      ignition::msgs::Link* l = models.at(ent.parent)->add_link();
      l->set_name(ent.name);
      l->set_id(e + 1);
      to_msg(ent.pose, *l->mutable_pose());
      for (size_t a = 0; a < w.antenna_mounts.size(); ++a)
        if (w.antenna_mounts[a].entity == e) {
          auto* s = l->add_sensor();
          s->set_name(w.antenna_mounts[a].sensor);
          s->set_id(1000 + a);
          to_msg(w.antenna_mounts[a].pose, *s->mutable_pose());
        }
    }
  }
  return scene;
}

inline ignition::msgs::Pose_V poses_at(const GazeboWorld& w, int64_t stamp_ns, bool second) {
  ignition::msgs::Pose_V v;
  v.mutable_header()->mutable_stamp()->set_sec(stamp_ns / 1000000000);
  v.mutable_header()->mutable_stamp()->set_nsec(static_cast<int32_t>(stamp_ns % 1000000000));
  for (const auto& [name, pose] : {std::pair{"robot", robot_pose(second)}, {"crate", crate_pose(second)}}) {
    auto* p = v.add_pose();
    p->set_name(name);
    p->set_id(w.find(name) + 1);
    to_msg(pose, *p);
  }
  auto* visual = v.add_pose();  // something the bridge does not track
  visual->set_name("visual");
  visual->set_id(999);
  return v;
}

// simulate() on the world in one of its two states: readings per antenna.
inline SimulationResult simulate_state(bool second, Scenario& scenario_out) {
  GazeboWorld w = load_world(world_options());
  w.entities[w.find("robot")].pose = robot_pose(second);
  w.entities[w.find("crate")].pose = crate_pose(second);
  w.place_sensors();
  Scenario s = w.scenario;
  s.seed = kSeed;
  s.duration_s = kDuration;
  s.channel = ChannelLevel::kLosBlocked;
  const auto channel = rfidray::make_channel(s.channel, s.channel_options, build_scene(w));
  scenario_out = s;
  return simulate(s, *channel);
}

using rfidray::testing::ChildProcess;
using rfidray::testing::slurp;
// `rfidray ARGS...`, killed (SIGKILL) at the end if still running.
using BridgeProcess = rfidray::testing::RfidrayProcess;


// Sends the t = 0 state until the bridge's BridgeStatus says it has one (discovery can drop the first
// messages), then simulation time runs to 2.075 s, a message every 50 ms, half a tick off the reader's ticks.
// False if the bridge never answered within 20 s.
inline bool play(const GazeboWorld& world, ignition::transport::Node::Publisher& poses,
                 const std::atomic<uint64_t>& status_poses, const BridgeProcess& bridge) {
  const auto until = std::chrono::steady_clock::now() + 20s;
  while (status_poses == 0 && std::chrono::steady_clock::now() < until && bridge.running()) {
    poses.Publish(poses_at(world, 0, false));
    std::this_thread::sleep_for(50ms);
  }
  if (status_poses == 0) return false;
  for (int64_t ns = 25000000; ns <= 2075000000; ns += 50000000) {
    poses.Publish(poses_at(world, ns, ns * 1e-9 >= kSwitch));
    std::this_thread::sleep_for(2ms);
  }
  return true;
}

// A partition of our own, on loopback only, so the test runs beside anything else on the machine.
inline std::string private_partition() {
  const std::string partition = "rfidray_test_" + std::to_string(getpid()) + "_" +
                                std::to_string(std::chrono::steady_clock::now().time_since_epoch().count());
  ::setenv("IGN_PARTITION", partition.c_str(), 1);
  ::setenv("IGN_IP", "127.0.0.1", 1);
  return partition;
}

// Gazebo's side: the scene/info service and the dynamic pose topic.
struct FakeGazebo {
  explicit FakeGazebo(const GazeboWorld& world) : scene(scene_of(world)) {
    reply = [this](const ignition::msgs::Empty&, ignition::msgs::Scene& rep) {
      rep = scene;
      return true;
    };
    advertised = node.Advertise("/world/rfid_test/scene/info", reply);
    poses = node.Advertise<ignition::msgs::Pose_V>("/world/rfid_test/dynamic_pose/info");
  }
  ignition::transport::Node node;
  ignition::msgs::Scene scene;
  std::function<bool(const ignition::msgs::Empty&, ignition::msgs::Scene&)> reply;
  bool advertised = false;
  ignition::transport::Node::Publisher poses;
};

}  // namespace rfidray::gazebo::fake
