// Built when tf2 / tf2_msgs were not found: the ROS pose input says what is missing.
#include <stdexcept>

#include "adapters/ros/pose_input.h"

namespace rfidray::ros_bridge {

struct PoseInput::Impl {};

PoseInput::PoseInput(const PoseInputOptions&) {
  throw std::runtime_error("rfidray was built without tf2 / tf2_msgs (Debian: libtf2-dev, libtf2-msgs-dev): no ROS "
                           "pose input; install them and rebuild");
}
PoseInput::~PoseInput() = default;
bool PoseInput::pop(InputEvent&, double) { return false; }
bool PoseInput::lookup(const std::string&, const std::string&, double, PoseValue&, std::string&) const { return false; }
std::string PoseInput::frames() const { return ""; }
std::string PoseInput::topics() const { return ""; }
uint64_t PoseInput::messages() const { return 0; }
uint64_t PoseInput::resets() const { return 0; }

}  // namespace rfidray::ros_bridge
