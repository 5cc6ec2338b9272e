#pragma once
// An antenna or tag endpoint at a position with the default pose orientation, gain and polarization: what the
// ray-tracing tests place at hand-picked points.
#include "core/channel.h"

namespace rfidray::testing {

inline Endpoint endpoint_at(const Vec3& position_m) {
  Endpoint e;
  e.pose.position = position_m;
  return e;
}

}  // namespace rfidray::testing
