#pragma once
// A Gazebo world that moves: poses arrive with their simulation time, and every antenna reads at its own
// update rate, tick k at t = k / update_rate, exactly as `rfidray simulate` would for the same poses and seed
// (core simulate_tick: same reader model, same random stream per (antenna, tick)).
//
// Timing: a tick at t_k uses the latest poses stamped at or before t_k, so it is computed once a message
// stamped later than t_k arrives (Gazebo publishes poses every step, far faster than readers tick). The first
// tick is the first one at or after the first message; a stamp a second or more back (a reset) starts the
// ticks again from there. Moving obstacles rebuild the radio scene before the next tick that traces through it.
//
// Two pose sources drive it: ign-transport Pose_V messages (apply, adapters/gazebo/bridge.cpp) and ROS 1 model
// states and TF (adapters/gazebo/ros_bridge.cpp), both as advance(t) then set_*_pose. An antenna whose pose at a
// tick comes from elsewhere (a TF chain looked up at the tick time) has a pose provider; it may block until its
// pose is known and throws InputError when it never is.
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <vector>

#include "adapters/gazebo/entity_map.h"
#include "adapters/gazebo/gazebo_world.h"
#include "core/channel.h"
#include "core/simulation.h"
#include "core/tag_couplings.h"

namespace rfidray::gazebo {

struct LiveOptions {
  uint64_t seed = 1;
  ChannelLevel channel = ChannelLevel::kIdeal;  // a fixed level: kAuto is refused
  double duration_s = std::numeric_limits<double>::infinity();  // ticks with t ≤ duration only
};

// One antenna tick: its reads (successful ones, tag order), the antenna's world pose, carrier and channel.
struct TickReadings {
  size_t antenna = 0;
  uint64_t tick = 0;
  double time_s = 0.0;
  Pose antenna_pose;
  double frequency_hz = 0.0;
  uint32_t hop_index = 0;  // index of the carrier in the reader's frequencies_hz
  std::vector<ReadRecord> reads;
};
using TickSink = std::function<void(const TickReadings&)>;
// World pose of antenna `a` at tick time t_s, or nullopt: the antenna follows its mount in the entity tree.
using AntennaPoseProvider = std::function<std::optional<Pose>(size_t antenna, double t_s)>;

// The world a bridge runs (either pose source): load_world, its warnings and notes printed to stderr as
// `rfidray: warning|note: ...`, and `model` ("" keeps the world's, else "paper" | "physical") applied to every
// antenna. Throws InputError naming the file when the world cannot be used or has no RFID antenna.
GazeboWorld load_bridge_world(const WorldOptions& world, const std::string& model);

// SIGINT/SIGTERM for either bridge: after install_stop_handlers(), stop_requested() turns true on the first
// signal (async-signal-safe: an atomic flag), so the bridge finishes its tick, writes its summary and exits.
void install_stop_handlers();
bool stop_requested();

class LiveWorld {
 public:
  LiveWorld(GazeboWorld world, const LiveOptions& options);

  GazeboWorld& world() { return world_; }
  const Scenario& scenario() const { return world_.scenario; }
  EntityMap& entity_map() { return map_; }

  // Applies the poses of a Pose_V stamped t_s, first emitting (in time order, antennas by index) every tick
  // the poses held so far cover. Entities it does not know are ignored; a pose that is not one
  // (checked_from_msg) is dropped and counted in rejected_poses(). Returns the ticks emitted.
  size_t apply(double t_s, const ignition::msgs::Pose_V& poses, const TickSink& sink);

  // Simulation time has reached t_s: emits (in time order, antennas by index) every tick before t_s that the
  // poses held so far cover. A first call starts the ticks at t_s; a t_s a second or more before the latest
  // (a reset) starts them again from there (then `restarted` is set). Non-finite t_s is ignored.
  size_t advance(double t_s, const TickSink& sink, bool* restarted = nullptr);
  // Poses after advance(): relative to the parent entity (a top-level model's parent is the world).
  void set_entity_pose(size_t entity, const Pose& relative_pose);
  void set_antenna_mount_pose(size_t antenna, const Pose& pose_in_entity);
  void set_tag_mount_pose(size_t tag, const Pose& pose_in_entity);
  void set_antenna_pose_provider(AntennaPoseProvider provider) { pose_provider_ = std::move(provider); }
  // True once every antenna's next tick lies beyond duration_s.
  bool finished() const;
  uint64_t ticks() const { return ticks_; }
  // Poses dropped by apply() as malformed, and which was the first ("" while none).
  uint64_t rejected_poses() const { return rejected_poses_; }
  const std::string& first_rejected_pose() const { return first_rejected_pose_; }
  uint64_t scene_builds() const { return scene_builds_; }
  double time_s() const { return time_s_; }
  bool started() const { return started_; }

 private:
  void emit_until(double t_s, const TickSink& sink, size_t& emitted);
  const Channel& channel();

  GazeboWorld world_;
  LiveOptions options_;
  EntityMap map_;
  std::vector<bool> moves_scene_;  // per entity: has collisions at or below it
  std::vector<uint64_t> next_tick_;
  bool started_ = false, scene_dirty_ = true, needs_trace_ = false;
  double time_s_ = 0.0;
  uint64_t ticks_ = 0, scene_builds_ = 0, rejected_poses_ = 0;
  std::string first_rejected_pose_;
  std::unique_ptr<Channel> channel_;
  IdealChannel ideal_;  // for paper-model antennas (they use the distance only)
  std::optional<TagCouplings> couplings_;  // built at the first tick
  AntennaPoseProvider pose_provider_;
};

}  // namespace rfidray::gazebo
