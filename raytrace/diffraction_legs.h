#pragma once
// The two legs of a first-order diffracted ray, antenna → edge point q → tag: whether both are clear. Shared by the
// diffraction loop (raytrace/diffraction.cpp) and the edge-end check (raytrace/edge_end_finder.h). Thread-safe
// (reads the scene only); nothing throws.
#include <algorithm>

#include "core/geometry.h"
#include "raytrace/embree_scene.h"

namespace rfidray {

// Each leg shot from the edge point q (Embree works in float: the ray's origin is where its precision matters, next
// to the faces that meet at the edge), starting and ending just off the edge and the ends. `s_hat_in` points from the
// antenna to q (length s_in), `s_hat_out` from q to the tag (length s_out).
inline bool legs_clear(const EmbreeScene& bvh, const Vec3& q, const Vec3& s_hat_in, double s_in, const Vec3& s_hat_out,
                       double s_out, double endpoint_epsilon_m) {
  const double end_in = std::min(endpoint_epsilon_m, 0.25 * s_in);
  const double end_out = std::min(endpoint_epsilon_m, 0.25 * s_out);
  return !bvh.occluded(q, -s_hat_in, end_in, s_in - end_in) && !bvh.occluded(q, s_hat_out, end_out, s_out - end_out);
}

}  // namespace rfidray
