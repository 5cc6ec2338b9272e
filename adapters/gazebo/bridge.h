#pragma once
// `rfidray gazebo`: the live bridge between a running Gazebo (Fortress generation, ign-transport 11) and the
// RFID model. It loads the same SDF world Gazebo runs, asks /world/<name>/scene/info for the entity tree (ids,
// names, current poses), follows /world/<name>/pose/info and /world/<name>/dynamic_pose/info (Pose_V, poses
// relative to the parent entity), and at every antenna tick publishes the readings:
//   ign-transport  <prefix>/<antenna>/readings   rfidray.msgs.TagReadings  (adapters/gazebo/msgs/rfid_readings.proto)
//                  <prefix>/status               rfidray.msgs.BridgeStatus, after every pose message applied
//   ROS 1          ~/<antenna>/data              rfid_sensor/TagArray (the seed plugin's message), with --ros
//   CSV            <dir>/<antenna>.csv           the rows of `rfidray simulate`, with --csv DIR
//
// Discovery: ign-transport finds peers by UDP multicast within one partition (IGN_PARTITION, or --partition;
// default hostname:username) on the interface IGN_IP names (or --ip). A message published before the peer's
// subscription is known is dropped, so nothing here depends on the first pose message (the scene/info reply
// carries the current poses), publishers wait up to --connect-timeout for their subscribers before the first
// tick, and BridgeStatus lets a peer re-send until it has been heard.
#include <limits>
#include <string>
#include <vector>

#include "adapters/gazebo/gazebo_world.h"

namespace rfidray::gazebo {

struct BridgeOptions {
  WorldOptions world;
  std::string world_name;  // "" = the SDF world's name
  uint64_t seed = 1;
  ChannelLevel channel = ChannelLevel::kIdeal;  // a fixed level
  std::string model;  // "" keeps each antenna's reader model
  std::string csv_dir;
  std::string topic_prefix = "/rfid";
  bool ros = false;
  std::string ros_node = "gazebo";  // the seed plugin publishes from the gazebo node: /gazebo/<antenna>/data
  std::string partition;            // "" = IGN_PARTITION (or GZ_PARTITION), else ign-transport's default
  std::string ip;                   // "" = IGN_IP as set
  double duration_s = std::numeric_limits<double>::infinity();
  double idle_timeout_s = std::numeric_limits<double>::infinity();  // stop after this long without poses
  double scene_timeout_s = 10.0;    // wait for the scene/info service
  double connect_timeout_s = 0.0;   // wait for readings subscribers before the first tick
  bool quiet = false;
};

// Runs until duration_s of simulation time has been read, the idle timeout, or SIGINT/SIGTERM. Throws
// InputError for a bad world or options; returns the exit code.
int run_bridge(const BridgeOptions& options);

}  // namespace rfidray::gazebo
