#pragma once
// `rfidray gazebo --input ros`: the live bridge driven over ROS 1, for Gazebo 11 (Classic) with gazebo_ros, the
// seed plugin's own setting, or any ROS system that publishes the same topics (a real robot). Same world import
// and tick core as the ign-transport bridge (live_world.h: tick k at k / update_rate in simulation time, the
// reader model and random streams of `rfidray simulate`), other pose inputs (adapters/ros/pose_input.h):
//   /gazebo/model_states  model poses in the world frame → the world's top-level models of the same name (their
//                         links, collisions, antennas and tags move with them). A name the world does not have
//                         is an error, unless listed in ignore_models.
//   /tf, /tf_static       an antenna with a TF frame (<frame> in its SDF sensor block, or `frames`) is at
//                         world_frame → frame, looked up at the tick time, ∘ the sensor's SDF <pose>. A chain
//                         that does not resolve within tf_timeout_s (wall time) is an error naming it.
//   /clock                the simulation time when /use_sim_time is set; else the newest /tf stamp.
// Time a second or more back (a reset) restarts the ticks from there, as with ign-transport.
// Output per tick: rfid_sensor/TagArray on <topic_namespace>/<antenna>/data (the seed plugin's topics with the
// default "/gazebo") and the rows of `rfidray simulate` in <csv_dir>/<antenna>.csv.
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "adapters/gazebo/gazebo_world.h"

namespace rfidray::gazebo {

struct RosBridgeOptions {
  WorldOptions world;
  uint64_t seed = 1;
  ChannelLevel channel = ChannelLevel::kIdeal;  // a fixed level
  std::string model;                            // "" keeps each antenna's reader model
  std::string csv_dir;
  std::string node_name = "rfidray";            // never "gazebo": a second node of that name stops Gazebo's
  std::vector<std::string> ros_args;            // "__name:=…", "from:=to" as roslaunch passes them
  std::string topic_namespace = "/gazebo";      // TagArray on <namespace>/<antenna>/data
  std::string world_frame = "world";            // TF frame of Gazebo's world; also TagArray's header.frame_id
  std::map<std::string, std::string> frames;    // antenna → TF frame (overrides the SDF's <frame>)
  std::vector<std::string> ignore_models;       // model_states names that are not in the world, knowingly
  std::string model_states_topic = "/gazebo/model_states";
  std::optional<bool> use_sim_time;             // unset: the /use_sim_time parameter
  double duration_s = std::numeric_limits<double>::infinity();
  double idle_timeout_s = std::numeric_limits<double>::infinity();  // wall s without input messages
  double tf_timeout_s = 5.0;       // wall s a tick waits for its antenna's TF chain
  double connect_timeout_s = 0.0;  // wall s to wait for TagArray subscribers before the first tick
  bool quiet = false;
};

// Runs until duration_s of simulation time, the idle timeout, or SIGINT/SIGTERM. Throws InputError for a bad
// world or options, no ROS master, an unknown model name or a TF chain that does not resolve; returns the exit
// code. Throws InputError when rfidray was built without the ROS pose input.
int run_ros_bridge(const RosBridgeOptions& options);

// The node's private ROS parameters (~name) as text (adapters/ros/ros_session.h), starting roscpp as
// `node_name`: the launch file's <param>s, which the command line overrides. `session` keeps roscpp running
// until run_ros_bridge has taken it over (roscpp does not start twice in one process).
struct RosParams {
  std::map<std::string, std::string> values;
  std::shared_ptr<void> session;
};
RosParams ros_private_params(const std::string& node_name, const std::vector<std::string>& ros_args);

}  // namespace rfidray::gazebo
