#pragma once
// roscpp once per process, shared by the ROS parts of the bridge (TagArrayPublisher, PoseInput): the first
// holder starts it as `node_name` (no SIGINT handler: the bridge has its own; no rosout), the last one to let
// go shuts it down. C++17, plain values. Not thread-safe: create and drop sessions from one thread.
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace rfidray::ros_bridge {

class RosSession {
 public:
  // `ros_args`: ROS's own command-line arguments ("__name:=rfidray", "__log:=…", "from:=to"), as roslaunch
  // passes them; __name overrides node_name. Throws std::runtime_error when no ROS master answers at
  // ROS_MASTER_URI (NodeHandle would block forever), or for an argument without ":=".
  static std::shared_ptr<RosSession> get(const std::string& node_name, const std::vector<std::string>& ros_args = {});
  ~RosSession();
  RosSession(const RosSession&) = delete;
  RosSession& operator=(const RosSession&) = delete;

  std::string node_name() const;  // resolved, e.g. "/rfidray"
  std::string master_uri() const;
  // The node's private parameters (~name) that are set, as text: strings as they are, numbers and booleans
  // printed, lists joined with ',' and dictionaries as "key=value" joined with ','. Keys without the '~'.
  std::map<std::string, std::string> private_params() const;
  // The global /use_sim_time parameter (false when unset).
  bool use_sim_time() const;

 private:
  RosSession() = default;
};

}  // namespace rfidray::ros_bridge
