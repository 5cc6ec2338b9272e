#pragma once
// Geometry helpers of the image method shared by the single-, double-bounce and diffraction searches
// (raytrace/path_finder.h). Pure functions; thread-safe.
#include <algorithm>
#include <cmath>

#include "core/geometry.h"

namespace rfidray {

// Mirror image of t in the plane n·x = c and the point where a→image meets the plane; false unless a and t
// are strictly on the same side (at least `eps` away from it).
inline bool image_point(const Vec3& n, double c, const Vec3& a, const Vec3& t, double eps, Vec3& image, Vec3& p) {
  const double da = n.dot(a) - c;
  const double dt = n.dot(t) - c;
  if (da * dt <= 0.0 || std::abs(da) < eps || std::abs(dt) < eps) return false;
  image = t - 2.0 * dt * n;
  p = a + (da / (da + dt)) * (image - a);
  return true;
}

// Distance along a leg leaving (or reaching) a plane at incidence cosine `cos_theta`, at which the leg is
// `eps` above the plane; capped so short legs are still tested over most of their length.
inline double plane_margin(double eps, double cos_theta, double leg_m) {
  return std::min(eps / std::max(cos_theta, 1e-9), 0.25 * leg_m);
}

}  // namespace rfidray
