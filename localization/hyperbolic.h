#pragma once
// Hyperbolic intersection, the paper's method (§III-D), in steps so each can be tested.
//
// Conics: inside each unwrapped segment the first read is the reference AP0 with phase distance m0; every
// time the antenna has moved ≥ stride from the last anchor, anchor n (AP_n, m_n) gives the conic
// |x − AP_n| − |x − AP0| = m_n − m0 (the unknown phase offset cancels). Stride = max(stride_m, usable path
// length / max_conics), so the O(n²) intersection stays bounded.
// Intersections: each new conic is intersected with all previous ones (any segment or channel: every conic
// is offset-free). 2-D: the plane sections at the known tag height; 3-D: the pair plus a third conic
// (the one of 8 evenly spread earlier anchors with the best geometry), Gauss–Newton from the pair's
// section intersections in the plane of the mean antenna height.
// Each intersection carries the unwrapped phase distance of its newer anchor and the quality E = 1/GDOP
// (position error per metre of range error, see hyperbolic.h/intersection_quality).
// Optimisation over the set: E-weighted kernel density (Gaussian, bandwidth h), its 5 strongest separated
// modes refined by mean shift at h, h/2, h/4; the estimate is the mode whose point best explains the whole
// unwrapped history (least range-cost SSR, range_cost.h).
#include <vector>

#include "localization/hyperbola.h"
#include "localization/methods.h"
#include "localization/prepare.h"

namespace rfidray::loc {

struct Intersection {
  Vec3 point = Vec3::Zero();
  double quality = 0.0;            // E = 1 / GDOP
  double phase_distance_m = 0.0;   // phiDist_n of the newer conic's anchor
  int conic_a = 0, conic_b = 0;
};

std::vector<Hyperbola> build_conics(const PreparedTag& prep, const LocalizeOptions& options, double* stride_used = nullptr);
std::vector<Intersection> intersect_conics(const std::vector<Hyperbola>& conics, const LocalizeOptions& options,
                                           double plane_height_m);
// Candidate modes of the intersection set (strongest first).
std::vector<Vec3> intersection_modes(const std::vector<Intersection>& set, double bandwidth_m, int max_modes);
// The mode reached by mean shift (bandwidth h, h/2, h/4) from `start`.
Vec3 intersection_mode_near(const std::vector<Intersection>& set, const Vec3& start, double bandwidth_m);

}  // namespace rfidray::loc
