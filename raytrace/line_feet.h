#pragma once
// Two points seen from a line, for the paths that go via one: a diffracting edge (raytrace/diffraction.cpp) and a thin
// post's axis (raytrace/post_scattering.cpp). Values only.
#include "core/geometry.h"

namespace rfidray {

// Two points seen from a line (a diffracting edge, a post's axis) through `origin` along the unit vector `d`: their
// coordinates along it and their perpendicular offsets from it. The unfolded path between them via the line is
// straight through the point dividing [z_a, z_t] in the ratio rho_a : rho_t (Fermat).
struct LineFeet {
  double z_a = 0.0, z_t = 0.0;
  Vec3 v_a = Vec3::Zero(), v_t = Vec3::Zero();
  double rho_a = 0.0, rho_t = 0.0;
};
inline LineFeet line_feet(const Vec3& origin, const Vec3& d, const Vec3& a, const Vec3& t) {
  LineFeet f;
  const Vec3 ra = a - origin, rt = t - origin;
  f.z_a = ra.dot(d);
  f.z_t = rt.dot(d);
  f.v_a = ra - f.z_a * d;
  f.v_t = rt - f.z_t * d;
  f.rho_a = f.v_a.norm();
  f.rho_t = f.v_t.norm();
  return f;
}

// The coordinate along the line of the point through which the unfolded path between the two points is straight
// (Fermat): it divides [z_a, z_t] in the ratio rho_a : rho_t. The Keller point of a diffracting edge.
inline double fermat_point_z(const LineFeet& f) { return f.z_a + (f.z_t - f.z_a) * f.rho_a / (f.rho_a + f.rho_t); }

}  // namespace rfidray
