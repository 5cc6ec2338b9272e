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

// The same with a linear polarization along its local z: a vertical dipole, E ∥ z (the edge-validity tests' source).
inline Endpoint z_dipole_at(const Vec3& position_m) {
  Endpoint e = endpoint_at(position_m);
  e.polarization.kind = PolarizationKind::kLinear;
  e.polarization.axis_local = Vec3::UnitZ();
  return e;
}

// A linear dipole along `axis_local` (normalized here), at a position: the double-bounce and diffraction tests' ends.
inline Endpoint linear_dipole_at(const Vec3& position_m, const Vec3& axis_local) {
  Endpoint e = endpoint_at(position_m);
  e.polarization.kind = PolarizationKind::kLinear;
  e.polarization.axis_local = axis_local.normalized();
  return e;
}

}  // namespace rfidray::testing
