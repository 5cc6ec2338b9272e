#pragma once
// The ROS 1 pose input of the live bridge: what a Gazebo 11 + gazebo_ros simulation (or a real robot) says
// about where things are. C++17 and plain values at its interface, like tag_array_publisher.h.
//
//   /gazebo/model_states  gazebo_msgs/ModelStates  top-level model poses in the world frame (no stamp: a
//                                                  message counts at the simulation time it arrives at)
//   /tf, /tf_static       tf2_msgs/TFMessage       into a tf2::BufferCore, for chains world frame → antenna frame
//   /clock                rosgraph_msgs/Clock      the simulation time, when /use_sim_time is set
//
// Time: with sim time, /clock; without, the newest stamp on /tf. A /tf stamp a second or more before the
// newest one (a simulator reset) clears the TF buffer (the /tf_static transforms are kept); the consumer sees
// the time go back and restarts its ticks. The buffer keeps tf_cache_s of transforms behind the newest.
// Messages are taken by one spinner thread in arrival order and queued without limit, so none is dropped;
// events come out of pop() in that order. Thread-safe: pop() and lookup() may run beside the spinner.
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "adapters/ros/tag_array_publisher.h"

namespace rfidray::ros_bridge {

struct NamedPose {
  std::string name;
  PoseValue pose;
};

struct InputEvent {
  enum class Kind { kTime, kModelStates };
  Kind kind = Kind::kTime;
  double time_s = 0.0;            // the simulation time when the message arrived
  std::vector<NamedPose> models;  // kModelStates: name and world pose of each model, as sent
};

struct PoseInputOptions {
  std::string node_name = "rfidray";
  std::string model_states_topic = "/gazebo/model_states";
  bool use_sim_time = false;  // time from /clock, else from /tf stamps
  double tf_cache_s = 30.0;   // how far back the TF buffer keeps transforms
};

class PoseInput {
 public:
  // Subscribes (RosSession::get(node_name) first) and starts the spinner. Throws std::runtime_error when no
  // ROS master answers.
  explicit PoseInput(const PoseInputOptions& options);
  ~PoseInput();
  PoseInput(const PoseInput&) = delete;
  PoseInput& operator=(const PoseInput&) = delete;

  // The next event, waiting up to wait_s; false when none came.
  bool pop(InputEvent& out, double wait_s);
  // Pose of `frame` in `world_frame` at time t_s (tf2 interpolates between stamps). False with tf2's reason in
  // `error` when the buffer cannot give it (yet).
  bool lookup(const std::string& world_frame, const std::string& frame, double t_s, PoseValue& out,
              std::string& error) const;
  // Every frame the buffer knows, "a, b, c", for messages.
  std::string frames() const;
  std::string topics() const;
  uint64_t messages() const;  // received so far, all topics
  uint64_t resets() const;    // times the TF buffer was cleared because time went back

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rfidray::ros_bridge
