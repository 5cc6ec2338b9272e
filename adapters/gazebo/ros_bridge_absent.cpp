// Built without rfidray_ros (roscpp, gencpp): the ROS pose input says what is missing.
#include "adapters/gazebo/ros_bridge.h"
#include "core/error.h"

namespace rfidray::gazebo {
namespace {
[[noreturn]] void missing() {
  throw InputError("--input ros: rfidray was built without roscpp / gencpp / tf2 (Debian: libroscpp-dev, "
                   "ros-message-generation, libtf2-dev, libtf2-msgs-dev); install them and rebuild");
}
}  // namespace

int run_ros_bridge(const RosBridgeOptions&) { missing(); }
RosParams ros_private_params(const std::string&, const std::vector<std::string>&) { missing(); }

}  // namespace rfidray::gazebo
