#pragma once
// A static antenna or tag of a scenario at a position, the rest default: what the simulation tests place by hand.
#include <string>

#include "core/scenario.h"

namespace rfidray::testing {

inline AntennaSpec fixed_antenna(const std::string& name, const Vec3& position_m) {
  AntennaSpec a;
  a.reader.name = name;
  a.motion.pose.position = position_m;
  return a;
}

inline TagSpec fixed_tag(const std::string& name, const Vec3& position_m) {
  TagSpec t;
  t.tag.name = name;
  t.motion.pose.position = position_m;
  return t;
}

}  // namespace rfidray::testing
