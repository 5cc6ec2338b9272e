#pragma once
// The closest points of two line segments: for edges near each other (raytrace/edge_pairs.cpp), a link passing an
// edge (raytrace/obstacle_finder.cpp, raytrace/edge_on_plate_finder.cpp). Values only; thread-safe; never throws.
#include <algorithm>

#include "core/geometry.h"

namespace rfidray {

// The closest points p0 + s·u and q0 + t·v of two segments, s ∈ [0, length_u_m], t ∈ [0, length_v_m], u and v unit
// vectors, and their distance in metres. Parallel segments (1 − (u·v)² ≤ 1e-12) take s = 0 and the t nearest to p0.
struct SegmentClosest {
  double s_m = 0.0, t_m = 0.0, distance_m = 0.0;
};

// C. Ericson, "Real-Time Collision Detection", 2005, §5.1.9: the lines' closest points, t clamped and s recomputed
// from the clamped t.
inline SegmentClosest closest_points(const Vec3& p0, const Vec3& u, double length_u_m, const Vec3& q0, const Vec3& v,
                                     double length_v_m) {
  const Vec3 r = p0 - q0;
  const double b = u.dot(v), c = u.dot(r), f = v.dot(r);
  const double denom = 1.0 - b * b;
  double s = denom > 1e-12 ? std::clamp((b * f - c) / denom, 0.0, length_u_m) : 0.0;
  double t = b * s + f;
  if (t < 0.0) {
    t = 0.0;
    s = std::clamp(-c, 0.0, length_u_m);
  } else if (t > length_v_m) {
    t = length_v_m;
    s = std::clamp(b * length_v_m - c, 0.0, length_u_m);
  }
  return {s, t, ((p0 + s * u) - (q0 + t * v)).norm()};
}

}  // namespace rfidray
