#pragma once
// The seed plugin's ROS 1 output: rfid_sensor/TagArray on ~/<antenna>/data of the node (default "gazebo", as
// the seed publishes from Gazebo's node: /gazebo/<antenna>/data). One message per antenna tick, also when no tag
// answered, as the seed does. Fields as the seed fills them: header.frame_id "world", header.stamp the
// simulation time of the tick, antennaPose the antenna's world pose, ntags, and per tag name, dist, phi, rssi
// with phi in (−π, π] (the seed's remainder(·, 2π); our CSV keeps [0, 2π)).
//
// This file and its .cpp are C++17: ROS 1's generated message code uses std::allocator::rebind, which C++20
// removed. So the interface takes plain values, nothing from our (C++20) headers.
#include <memory>
#include <string>
#include <vector>

namespace ros {
class NodeHandle;
class Publisher;
}  // namespace ros

namespace rfidray::cli::ros_bridge {

struct TagValue {
  std::string name;
  double dist = 0.0, phase_rad = 0.0, rssi = 0.0;
};

// Position x, y, z and orientation quaternion x, y, z, w (world frame).
struct PoseValue {
  double x = 0, y = 0, z = 0, qx = 0, qy = 0, qz = 0, qw = 1;
};

class TagArrayPublisher {
 public:
  // ros::init as `node_name` and one publisher per antenna. Throws std::runtime_error when no ROS master
  // answers at ROS_MASTER_URI.
  TagArrayPublisher(const std::string& node_name, const std::vector<std::string>& antennas);
  ~TagArrayPublisher();
  std::string topics() const;
  bool all_connected() const;  // every topic has a subscriber
  void publish(size_t antenna, double time_s, const PoseValue& antenna_pose, const std::vector<TagValue>& tags);

 private:
  std::unique_ptr<ros::NodeHandle> node_;
  std::vector<ros::Publisher> publishers_;
};

}  // namespace rfidray::cli::ros_bridge
