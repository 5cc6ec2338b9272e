// `rfidray gazebo` over real ign-transport on loopback: this test plays Gazebo (the scene/info service and
// Pose_V on dynamic_pose/info) in a partition of its own; the bridge runs as a separate process, moves the
// robot's antenna and the crate, and publishes readings. They must arrive, and equal `simulate` for the same
// poses and seed, tick by tick: its CSV byte for byte, its TagReadings value for value.
#include <gtest/gtest.h>
#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <ignition/msgs/empty.pb.h>
#include <ignition/msgs/pose_v.pb.h>
#include <ignition/msgs/scene.pb.h>
#include <ignition/transport/Node.hh>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <thread>

#include "cli/gazebo/entity_map.h"
#include "cli/gazebo/gazebo_world.h"
#include "cli/gazebo/msgs/rfid_readings.pb.h"
#include "cli/readings_csv.h"
#include "cli/world_source.h"
#include "core/simulation.h"
#include "core/units.h"

extern char** environ;

namespace rfidray::cli::gazebo {
namespace {

namespace fs = std::filesystem;
using namespace std::chrono_literals;
const std::string kDir = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/tests/gazebo";
constexpr uint64_t kSeed = 7;
constexpr double kDuration = 2.0, kSwitch = 0.975;  // poses change between ticks (reader 10 Hz, gate 5 Hz)

WorldOptions world_options() {
  WorldOptions o;
  o.file = kDir + "/rfid_test.world";
  o.resource_path = {kDir + "/models"};
  return o;
}

// The two states Gazebo goes through: the robot (antenna "reader") drives and turns, and the crate is
// moved between the gate antenna and tag_2 (so the traced channel changes too).
Pose robot_pose(bool second) {
  return second ? Pose{Vec3(1.0, -1.0, 0.0), Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()))} : Pose{};
}
Pose crate_pose(bool second) {
  // Turned 90°: x in [0.5, 2.5], y in [2.5, 3.5], z in [1, 2]; the gate–tag_2 line crosses its faces y = 3.5, 2.5.
  return second ? Pose{Vec3(1.5, 3.0, 1.5), Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()))}
                : Pose{Vec3(-2, 3, 0.5), Quat::Identity()};
}

// Gazebo's ids for our entities: index + 1; sensors 1000 + mount.
ignition::msgs::Scene scene_of(const GazeboWorld& w) {
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

ignition::msgs::Pose_V poses_at(const GazeboWorld& w, int64_t stamp_ns, bool second) {
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
SimulationResult simulate_state(bool second, Scenario& scenario_out) {
  GazeboWorld w = load_world(world_options());
  w.entities[w.find("robot")].pose = robot_pose(second);
  w.entities[w.find("crate")].pose = crate_pose(second);
  w.place_sensors();
  Scenario s = w.scenario;
  s.seed = kSeed;
  s.duration_s = kDuration;
  s.channel = "los+blocked";
  const auto channel = make_scene_channel(s.channel, build_scene(w), "channel");
  scenario_out = s;
  return simulate(s, *channel);
}

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

class BridgeProcess {
 public:
  BridgeProcess(const std::vector<std::string>& args, const fs::path& log) {
    std::vector<std::string> argv{RFIDRAY_BINARY};
    argv.insert(argv.end(), args.begin(), args.end());
    std::vector<char*> cargv;
    for (auto& a : argv) cargv.push_back(a.data());
    cargv.push_back(nullptr);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    if (posix_spawn(&pid_, cargv[0], &fa, nullptr, cargv.data(), environ) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&fa);
  }
  ~BridgeProcess() {
    if (pid_ > 0 && !done_) {
      kill(pid_, SIGKILL);
      waitpid(pid_, nullptr, 0);
    }
  }
  bool running() const { return pid_ > 0 && !done_; }
  // Exit status, or −1 if it did not exit within the timeout (it is then killed).
  int wait(std::chrono::milliseconds timeout) {
    const auto until = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < until) {
      int st = 0;
      if (waitpid(pid_, &st, WNOHANG) == pid_) {
        done_ = true;
        return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
      }
      std::this_thread::sleep_for(10ms);
    }
    return -1;
  }

 private:
  pid_t pid_ = -1;
  bool done_ = false;
};

TEST(BridgeLoopback, ReadingsArriveAndMatchSimulate) {
  // A partition of our own, on loopback only: runs in parallel with anything else on this machine.
  const std::string partition = "rfidray_test_" + std::to_string(getpid()) + "_" +
                                std::to_string(std::chrono::steady_clock::now().time_since_epoch().count());
  ::setenv("IGN_PARTITION", partition.c_str(), 1);
  ::setenv("IGN_IP", "127.0.0.1", 1);
  const fs::path dir = fs::temp_directory_path() / partition;
  fs::create_directories(dir);

  GazeboWorld world = load_world(world_options());
  ignition::transport::Node gazebo;
  const ignition::msgs::Scene scene = scene_of(world);
  std::function<bool(const ignition::msgs::Empty&, ignition::msgs::Scene&)> scene_info =
      [&](const ignition::msgs::Empty&, ignition::msgs::Scene& rep) {
        rep = scene;
        return true;
      };
  ASSERT_TRUE(gazebo.Advertise("/world/rfid_test/scene/info", scene_info));
  auto poses = gazebo.Advertise<ignition::msgs::Pose_V>("/world/rfid_test/dynamic_pose/info");

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
  ASSERT_TRUE(gazebo.Subscribe("/rfid/reader/readings", on_readings));
  ASSERT_TRUE(gazebo.Subscribe("/rfid/gate/readings", on_readings));
  ASSERT_TRUE(gazebo.Subscribe("/rfid/status", on_status));

  BridgeProcess bridge({"gazebo", "--world", world_options().file, "--resource-path", kDir + "/models", "--seed",
                        std::to_string(kSeed), "--channel", "los+blocked", "--duration", "2", "--csv", dir.string(),
                        "--idle-timeout", "20", "--connect-timeout", "10", "--scene-timeout", "20"},
                       dir / "bridge.log");
  ASSERT_TRUE(bridge.running());

  // Discovery can drop the first messages: send the t = 0 state until the bridge says it has one.
  const auto until = std::chrono::steady_clock::now() + 20s;
  while (status_poses == 0 && std::chrono::steady_clock::now() < until && bridge.running()) {
    poses.Publish(poses_at(world, 0, false));
    std::this_thread::sleep_for(50ms);
  }
  ASSERT_GT(status_poses.load(), 0u) << "the bridge never acknowledged a pose message; its log:\n"
                                     << slurp(dir / "bridge.log");
  // Then simulation time runs: a message every 50 ms of simulation time, half a tick off the reader's ticks.
  for (int64_t ns = 25000000; ns <= 2075000000; ns += 50000000) {
    poses.Publish(poses_at(world, ns, ns * 1e-9 >= kSwitch));
    std::this_thread::sleep_for(2ms);
  }
  ASSERT_EQ(bridge.wait(20000ms), 0) << "bridge log:\n" << slurp(dir / "bridge.log");

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
    csv << kReadingsHeader << '\n';
    write_readings_rows(csv, s1, a, expected);
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
}  // namespace rfidray::cli::gazebo
