#include "core/polarization.h"

#include <cmath>

#include "core/error.h"

namespace rfidray {
namespace {

Vec3 transverse(const Vec3& a, const Vec3& dir) { return a - a.dot(dir) * dir; }

}  // namespace

CVec3 Polarization::field(const Quat& orientation, const Vec3& dir) const {
  using C = std::complex<double>;
  // Unrotated antennas are common (tags, test setups): skip the quaternion product.
  const Vec3 axis = orientation.w() == 1.0 ? axis_local : Vec3(orientation * axis_local);
  Vec3 u = transverse(axis, dir);
  if (kind == PolarizationKind::kLinear) {
    const double n = u.norm();
    if (n < 1e-12) return CVec3::Zero();  // looking down the wire: no radiated field
    return (u / n).cast<C>();
  }
  // Circular: the reference axis only fixes the phase; pick any transverse axis if it is degenerate.
  if (u.norm() < 1e-9) u = transverse(orientation * Vec3::UnitX(), dir);
  if (u.norm() < 1e-9) u = transverse(orientation * Vec3::UnitY(), dir);
  u.normalize();
  const Vec3 v = dir.cross(u);  // u × v = dir
  // e^{jωt} convention: (u − j v)/√2 turns from u towards v, i.e. right-handed about dir (IEEE RHCP).
  const C sign = kind == PolarizationKind::kCircularRight ? C(0, -1) : C(0, 1);
  return (u.cast<C>() + sign * v.cast<C>()) / std::sqrt(2.0);
}

std::complex<double> polarization_match(const CVec3& incoming_field, const Polarization& rx,
                                        const Quat& rx_orientation, const Vec3& arrival_direction_world) {
  if (rx.kind == PolarizationKind::kLinear) {
    // A real field vector: real × complex products, once per path in the tracer's inner loop.
    const Vec3 dir = -arrival_direction_world;
    const Vec3 axis = rx_orientation.w() == 1.0 ? rx.axis_local : Vec3(rx_orientation * rx.axis_local);
    const Vec3 u = transverse(axis, dir);
    const double n = u.norm();
    if (n < 1e-12) return 0.0;
    return (u.x() * incoming_field.x() + u.y() * incoming_field.y() + u.z() * incoming_field.z()) / n;
  }
  const CVec3 e_rx = rx.field(rx_orientation, -arrival_direction_world);
  return e_rx.transpose() * incoming_field;
}

PolarizationKind parse_polarization_kind(const std::string& name, const std::string& field) {
  if (name == "linear") return PolarizationKind::kLinear;
  if (name == "rhcp" || name == "circular") return PolarizationKind::kCircularRight;
  if (name == "lhcp") return PolarizationKind::kCircularLeft;
  throw field_error(field, "unknown polarization '" + clip(name) + "' (linear, rhcp, lhcp; circular = rhcp)");
}

const char* to_string(PolarizationKind kind) {
  switch (kind) {
    case PolarizationKind::kLinear: return "linear";
    case PolarizationKind::kCircularRight: return "rhcp";
    case PolarizationKind::kCircularLeft: return "lhcp";
  }
  return "?";
}

}  // namespace rfidray
