#pragma once
// Antenna polarization as a unit complex field vector (Jones vector in 3-D), world frame.
// Linear: along a local axis, projected transverse to the propagation direction.
// Circular: (u ∓ j v)/√2 in the transverse plane, v = k̂ × u, e^{jωt}; right-hand (RHCP, u − j v) rotates
// right-handed about the propagation direction k̂, i.e. clockwise seen looking along k̂ (IEEE convention).
#include <complex>
#include <string>

#include "core/geometry.h"

namespace rfidray {

using CVec3 = Eigen::Matrix<std::complex<double>, 3, 1>;

enum class PolarizationKind { kLinear, kCircularRight, kCircularLeft };

struct Polarization {
  PolarizationKind kind = PolarizationKind::kLinear;
  Vec3 axis_local = Vec3::UnitZ();  // linear: the E-field axis in the antenna frame

  // Field vector radiated towards `direction_world` (unit) by an antenna with `orientation`.
  // Transverse to the direction, unit norm; zero if a linear axis is parallel to the direction.
  CVec3 field(const Quat& orientation, const Vec3& direction_world) const;
};

// Polarization match of an incoming field at a receiving antenna, as a complex amplitude factor.
// By reciprocity the received voltage is e_rx · e_in (no conjugate), with e_rx the field the receiver
// would itself radiate back towards the source (direction −arrival). Matched CP pairs give 1,
// opposite hands 0, linear vs CP 1/√2.
std::complex<double> polarization_match(const CVec3& incoming_field, const Polarization& rx,
                                        const Quat& rx_orientation, const Vec3& arrival_direction_world);

PolarizationKind parse_polarization_kind(const std::string& name, const std::string& field);
const char* to_string(PolarizationKind kind);

}  // namespace rfidray
