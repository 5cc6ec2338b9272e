// Level double-bounce: every specular path with two reflections, by the image of the image
// (raytrace/path_finder.h has the physics). Both candidate modes walk every ordered pair of distinct planes (less
// the pairs whose sign tests fail, skipped per second plane without a visit: double_reflections):
//  - exact: the occupancy bitmaps reject points with no facet near them, then one closest-hit ray per leg says
//    which facet is at P1 (the ray A→P1) and at P2 (the ray P1→P2) and that the leg is clear;
//  - exhaustive: the points are tested against every facet of their plane (point in triangle) and every leg
//    by an occlusion ray. Both give the same paths (tests/raytrace/test_double_bounce.cpp).
// Links traced together (trace_sum) share the pair scan: per block of nearby tags, plane_pairs_near keeps
// only the pairs whose reflection points can land on occupied cells for some tag of the block, and each link
// of the block walks those (tests/raytrace/test_double_bounce.cpp: the same paths as every pair).
#include <algorithm>
#include <cmath>

#include "core/fresnel.h"
#include "core/units.h"
#include "raytrace/bit_grid.h"
#include "raytrace/image_geometry.h"
#include "raytrace/path_finder.h"

namespace rfidray {

// Defined before its callers (double_reflections) and inline: per link it runs n² times and most pairs end in it.
inline void PathFinder::try_plane_pair(uint32_t g1, uint32_t g2, const Endpoint& ant, const Endpoint& tag, double f,
                                       const PoseCandidates& c, double floor, const LinkImages& images,
                                       std::vector<TracedPath>& out) const {
  ++tl_plane_pairs_tried;
  const PlaneGroup& a_plane = planes_[g1];
  const PlaneGroup& b_plane = planes_[g2];
  const Vec3& a = ant.pose.position;
  const double eps = options_.surface_epsilon_m;
  // T2: the tag's image in plane 2. T21: T2's image in plane 1; P1 on plane 1 between A and T21. (image_point,
  // written out with the link's table: the same expressions, so the same values.)
  //
  // The sign and distance tests are combined without branching (most pairs fail one of them, unpredictably,
  // and a mispredicted branch costs more than the divisions done for a pair that fails): each value is what the
  // branching code would have computed for a pair that passes, and a pair that fails is dropped as before.
  const double dt2 = images.tag_offset_m[g2];
  const Vec3& t2 = images.tag_image[g2];
  const double da = images.antenna_offset_m[g1];
  const double dt = a_plane.normal.dot(t2) - a_plane.offset_m;
  const Vec3 t21 = t2 - 2.0 * dt * a_plane.normal;
  const Vec3 p1 = a + (da / (da + dt)) * (t21 - a);
  // P2 on plane 2 between P1 and T2 (P1 and T strictly on one side of plane 2); T's image there is T2.
  const double dp = b_plane.normal.dot(p1) - b_plane.offset_m;
  const Vec3 p2 = p1 + (dp / (dp + dt2)) * (t2 - p1);
  // (Each test is the negation of image_point's and the length test's rejection, as written there.)
  const bool pass = !(std::abs(dt2) < eps) & !(da * dt <= 0.0) & !(std::abs(da) < eps) & !(std::abs(dt) < eps) &
                    !((t21 - a).squaredNorm() > max_length2_) & !(dp * dt2 <= 0.0) & !(std::abs(dp) < eps);
  if (!pass) return;
  const bool exhaustive = options_.candidates == CandidateMode::kExhaustive;
  // Cheap rejections first: no facet near P1 or P2 (the occupancy grids, conservative).
  const size_t bit1 = cell_bit(a_plane, p1), bit2 = cell_bit(b_plane, p2);
  if (bit1 == SIZE_MAX || bit2 == SIZE_MAX) return;
  if (!((occupancy_[bit2 / 64] >> (bit2 % 64)) & 1u)) return;
  if (c.all || exhaustive) {
    if (!((occupancy_[bit1 / 64] >> (bit1 % 64)) & 1u)) return;
  } else if (!((c.seen_cells[bit1 / 64] >> (bit1 % 64)) & 1u)) {
    return;  // P1 not seen from the antenna by the candidate rays
  }
  trace_plane_pair(g1, g2, ant, tag, f, floor, t21, p1, p2, out);
}

void PathFinder::double_reflections(const Endpoint& ant, const Endpoint& tag, double f, const PoseCandidates& c,
                                    double floor, const std::vector<PlanePair>* pairs,
                                    std::vector<TracedPath>& out) const {
  const auto n = static_cast<uint32_t>(planes_.size());
  // Each plane's offsets of A and T and T's image, once per link instead of once per pair (n instead of n²).
  thread_local LinkImages tl_images;  // per-thread scratch: no allocation once warm
  LinkImages& images = tl_images;
  images.antenna_offset_m.resize(n);
  images.tag_offset_m.resize(n);
  images.tag_image.resize(n);
  const Vec3& a = ant.pose.position;
  const Vec3& t = tag.pose.position;
  for (uint32_t g = 0; g < n; ++g) {
    const PlaneGroup& plane = planes_[g];
    images.antenna_offset_m[g] = plane.normal.dot(a) - plane.offset_m;
    const double dt = images.tag_offset_m[g] = plane.normal.dot(t) - plane.offset_m;
    images.tag_image[g] = t - 2.0 * dt * plane.normal;
  }
  if (pairs) {  // the pairs plane_pairs_near kept for this link's block (trace_sum sorts the paths afterwards)
    for (const PlanePair& p : *pairs) try_plane_pair(p.first, p.second, ant, tag, f, c, floor, images, out);
    return;
  }
  // Every ordered pair (g1, g2), except pairs that try_plane_pair would reject by its sign tests, found per second
  // plane without visiting them (they are counted as tried; the order of the pairs changes, not the paths: trace_impl
  // sorts them). For an axis-aligned plane n = σ·e_k, n·x − c = σ(x_k − σc) has the sign of x_k − x_plane, rounded
  // alike, so the tests read as comparisons of coordinates:
  //  (1) A and T2 (T's image in plane 2) strictly on one side of plane 1: a first plane whose coordinate lies between
  //      A's and T2's along its axis is rejected;
  //  (2) P1 and T strictly on one side of plane 2, at least ε off it. P1 lies on plane 1; for a first plane
  //      perpendicular to plane 2, P1's coordinate along plane 2's axis lies between A's and T2's (T2 is across plane 2
  //      from T), so A and T strictly across plane 2 from each other reject every perpendicular first plane; for a
  //      parallel one, P1's coordinate is plane 1's, which must lie strictly on T's side of plane 2. Rounding moves P1
  //      by a few ulps of the coordinates, far below ε (guarded: scale_ok), so a P1 that rounding would carry across
  //      is rejected by |n·P1 − c| < ε anyway.
  const double eps = options_.surface_epsilon_m;
  const double scale = std::max({a.cwiseAbs().maxCoeff(), t.cwiseAbs().maxCoeff(), max_plane_coordinate_m_});
  const bool scale_ok = eps >= 1e-12 * scale;
  const auto below = [](const AxisPlane& p, double x) { return p.coordinate_m < x; };
  const auto above = [](double x, const AxisPlane& p) { return x < p.coordinate_m; };
  // Plane 2's own entry in the axis list being walked (nullptr when it is not in that list): the one plane of a run
  // that makes no pair with it.
  const AxisPlane* self = nullptr;
  // The pairs of a skipped run [begin, end) of first planes, counted without walking it.
  const auto count = [&](const AxisPlane* begin, const AxisPlane* end) {
    tl_plane_pairs_tried += static_cast<uint64_t>(end - begin) - (self != nullptr && self >= begin && self < end);
  };
  // The first planes of a sorted run [begin, end) with plane 2: tries those whose coordinate lies outside [lo, hi],
  // counts the others (rejected by (1)).
  const auto try_outside = [&](uint32_t g2, const AxisPlane* begin, const AxisPlane* end, double lo, double hi) {
    const AxisPlane* first_in = std::lower_bound(begin, end, lo, below);
    const AxisPlane* first_after = std::upper_bound(first_in, end, hi, above);
    for (const AxisPlane* it = begin; it != first_in; ++it)
      if (it->plane != g2) try_plane_pair(it->plane, g2, ant, tag, f, c, floor, images, out);
    for (const AxisPlane* it = first_after; it != end; ++it)
      if (it->plane != g2) try_plane_pair(it->plane, g2, ant, tag, f, c, floor, images, out);
    count(first_in, first_after);
  };
  for (uint32_t g2 = 0; g2 < n; ++g2) {
    const PlaneGroup& second = planes_[g2];
    const Vec3& t2 = images.tag_image[g2];
    const bool axis_aligned = second.axis_sign != 0 && scale_ok;
    const int k2 = second.axis_k;
    const double x2 = second.axis_sign * second.offset_m;
    // T's side of plane 2 along its axis (+1 / −1; 0 on it: every pair is rejected by |dt2| < ε, left to the test).
    const double t_off = axis_aligned ? t[k2] - x2 : 0.0, a_off = axis_aligned ? a[k2] - x2 : 0.0;
    const bool across = axis_aligned && ((t_off > 0.0 && a_off < 0.0) || (t_off < 0.0 && a_off > 0.0));
    for (int k = 0; k < 3; ++k) {
      const std::vector<AxisPlane>& list = planes_by_axis_[k];
      const AxisPlane* begin = list.data();
      const AxisPlane* end = list.data() + list.size();
      self = second.axis_sign != 0 && k == second.axis_k ? begin + axis_position_[g2] : nullptr;
      const double lo = std::min(a[k], t2[k]), hi = std::max(a[k], t2[k]);
      if (!axis_aligned || (k != k2 && t_off == 0.0)) {
        try_outside(g2, begin, end, lo, hi);  // (1) only
      } else if (k != k2) {
        if (across) count(begin, end);  // (2): every perpendicular first plane
        else try_outside(g2, begin, end, lo, hi);
      } else if (t_off == 0.0) {
        try_outside(g2, begin, end, lo, hi);
      } else {
        // (2) for parallel first planes: only those strictly on T's side of plane 2, then (1) among them.
        const AxisPlane* split_lo = std::lower_bound(begin, end, x2, below);  // first with x ≥ x2
        const AxisPlane* split_hi = std::upper_bound(split_lo, end, x2, above);  // first with x > x2
        if (t_off > 0.0) {
          count(begin, split_hi);
          try_outside(g2, split_hi, end, lo, hi);
        } else {
          try_outside(g2, begin, split_lo, lo, hi);
          count(split_lo, end);
        }
      }
    }
    for (const uint32_t g1 : planes_off_axis_)
      if (g1 != g2) try_plane_pair(g1, g2, ant, tag, f, c, floor, images, out);
  }
}

// A pair whose points P1, P2 passed try_plane_pair's rejections: the bound, the rays, the field.
void PathFinder::trace_plane_pair(uint32_t g1, uint32_t g2, const Endpoint& ant, const Endpoint& tag, double f,
                                  double floor, Vec3 t21, Vec3 p1, Vec3 p2, std::vector<TracedPath>& out) const {
  const PlaneGroup& a_plane = planes_[g1];
  const PlaneGroup& b_plane = planes_[g2];
  const Vec3& a = ant.pose.position;
  const Vec3& t = tag.pose.position;
  const double eps = options_.surface_epsilon_m;
  const bool exhaustive = options_.candidates == CandidateMode::kExhaustive;
  Vec3 t2_again;
  const double length = (t21 - a).norm();
  const Vec3 dir1 = (p1 - a).normalized(), dir3 = (t - p2).normalized();
  const double gain = std::sqrt(ant.pattern.gain_linear_world(ant.pose.orientation, dir1) *
                                tag.pattern.gain_linear_world(tag.pose.orientation, -dir3));
  // |Γ| ≤ 1 at each bounce and a polarization match ≤ 1: an upper bound of the contribution. Below the drop
  // floor the path would be dropped anyway: no ray for it.
  const double bound = gain * wavelength_m(f) / (4.0 * kPi * length);
  if (bound * bound < floor) return;

  const EmbreeScene& bvh = scene_->bvh();
  const auto& facets = scene_->facets();
  uint32_t f1 = kNoFacet, f2 = kNoFacet;
  const double l1 = (p1 - a).norm(), l2 = (p2 - p1).norm();
  if (!(l1 > 0.0) || !(l2 > 0.0)) return;
  const Vec3 dir2 = (p2 - p1) / l2;
  if (exhaustive) {
    for (uint32_t m : plane_members_[g1])
      if (point_on_facet(facets[m], p1)) {
        f1 = m;
        break;
      }
    for (uint32_t m : plane_members_[g2])
      if (point_on_facet(facets[m], p2)) {
        f2 = m;
        break;
      }
    if (f1 == kNoFacet || f2 == kNoFacet) return;
  } else {
    // The first thing on A→P1 must be a facet of plane 1, the first thing on P1→P2 one of plane 2.
    const double m1 = plane_margin(eps + a_plane.flatness_m, std::abs(dir1.dot(a_plane.normal)), l1);
    const RayHit h1 = bvh.intersect(a, dir1, std::min(options_.endpoint_epsilon_m, 0.25 * l1), l1 + m1);
    if (!h1.hit) return;
    f1 = scene_->facet_of(scene_->triangle_id(h1.geom, h1.prim));
    if (f1 == kNoFacet || plane_of_facet_[f1] != g1) return;
    const double start = plane_margin(eps + a_plane.flatness_m, std::abs(dir2.dot(a_plane.normal)), l2);
    const double m2 = plane_margin(eps + b_plane.flatness_m, std::abs(dir2.dot(b_plane.normal)), l2);
    const RayHit h2 = bvh.intersect(p1, dir2, start, l2 + m2);
    if (!h2.hit) return;
    f2 = scene_->facet_of(scene_->triangle_id(h2.geom, h2.prim));
    if (f2 == kNoFacet || plane_of_facet_[f2] != g2) return;
  }
  // A thin post's faces are not mirrors at the levels that model it (raytrace/post_scattering.cpp).
  if (is_post_facet(f1) || is_post_facet(f2)) return;
  // Redo the images in the facets' own planes (identical to the groups' within the grouping tolerance).
  const Facet& fa = facets[f1];
  const Facet& fb = facets[f2];
  const double dt = fb.signed_distance(t);
  if (std::abs(dt) < eps) return;
  const Vec3 t2f = t - 2.0 * dt * fb.normal;
  if (!image_point(fa.normal, fa.offset_m, a, t2f, eps, t21, p1)) return;
  if (!image_point(fb.normal, fb.offset_m, p1, t, eps, t2_again, p2)) return;
  const Vec3 d1 = p1 - a, d2 = p2 - p1, d3 = t - p2;
  const double len1 = d1.norm(), len2 = d2.norm(), len3 = d3.norm();
  if (!(len1 > 0.0) || !(len2 > 0.0) || !(len3 > 0.0)) return;
  const Vec3 u1 = d1 / len1, u2 = d2 / len2, u3 = d3 / len3;
  const double cos1 = std::abs(u1.dot(fa.normal)), cos2 = std::abs(u2.dot(fb.normal));
  const double clear1 = eps + fa.flatness_m, clear2 = eps + fb.flatness_m;
  const double end1 = std::min(options_.endpoint_epsilon_m, 0.25 * len1);
  const double end3 = std::min(options_.endpoint_epsilon_m, 0.25 * len3);
  if (exhaustive) {
    // From the facet back to the antenna: precision is needed next to the facet (path_finder.cpp, leg 1).
    if (bvh.occluded(p1, -u1, plane_margin(clear1, cos1, len1), len1 - end1)) return;
    if (bvh.occluded(p1, u2, plane_margin(clear1, cos1, len2), len2 - plane_margin(clear2, cos2, len2))) return;
  }
  if (bvh.occluded(p2, u3, plane_margin(clear2, cos2, len3), len3 - end3)) return;

  const CVec3 e0 = ant.polarization.field(ant.pose.orientation, u1);
  const CVec3 e1 = reflect_field(e0, u1, fa.normal, material_reflection(scene_->materials()[fa.material], f, cos1));
  const CVec3 e2 = reflect_field(e1, u2, fb.normal, material_reflection(scene_->materials()[fb.material], f, cos2));
  const double g = std::sqrt(ant.pattern.gain_linear_world(ant.pose.orientation, u1) *
                             tag.pattern.gain_linear_world(tag.pose.orientation, -u3));
  TracedPath path;
  path.kind = PathKind::kReflection2;
  path.length_m = (t21 - a).norm();
  path.point = p1;
  path.material = fa.material;
  path.facet = f1;
  path.point2 = p2;
  path.material2 = fb.material;
  path.facet2 = f2;
  path.coefficient = g * polarization_match(e2, tag.polarization, tag.pose.orientation, u3);
  path.contribution = path_contribution(path.length_m, path.coefficient, f);
  out.push_back(path);
}

// The reflection point P between an apex X and a point T on one side of an axis-aligned plane (n = σ·e_k,
// n·x = c) is X + s (T − X) in the plane's two other coordinates, s = d_X / (d_X + d_T) with d the signed
// distances (one sign). Over a box of T it is bounded by the box's corners: for fixed d_T it is linear in
// T's coordinate, for a fixed coordinate monotone in d_T (d_X + d_T keeps its sign), and the two vary
// independently in a box. The margin covers the per-link computation's rounding: its point is off the exact
// one by a few ulps of the coordinates divided by the cosine of the incidence, and that cosine is at least
// d_min / L, L the apex's largest distance from the box mirrored in the plane (the unfolded leg): 1e-12 is
// 10⁴ times the few ulps (2⁻⁵³ relative) of that computation.
bool PathFinder::reflection_window(const PlaneGroup& g, const Vec3& apex, const Vec3& lo, const Vec3& hi,
                                   double region[2][2], double* margin_m, double* amplification) const {
  if (g.axis_sign == 0) return false;
  const int k = g.axis_k;
  const double s = g.axis_sign, c = g.offset_m;
  const double d_apex = s * apex[k] - c;
  const double dt_lo = (s > 0 ? lo[k] : -hi[k]) - c, dt_hi = (s > 0 ? hi[k] : -lo[k]) - c;
  constexpr double kTiny = 1e-150;
  const bool one_side = (d_apex > kTiny && dt_lo > kTiny) || (d_apex < -kTiny && dt_hi < -kTiny);
  if (!one_side) return false;
  const double d_lo = d_apex + dt_lo, d_hi = d_apex + dt_hi;
  const double d_min = std::min(std::abs(d_lo), std::abs(d_hi));
  // The box mirrored in the plane (only coordinate k changes) and its farthest corner from the apex.
  const double plane_x = s * c;
  Vec3 far = (apex - lo).cwiseAbs().cwiseMax((apex - hi).cwiseAbs());
  far[k] = std::max(std::abs(2.0 * plane_x - lo[k] - apex[k]), std::abs(2.0 * plane_x - hi[k] - apex[k]));
  const double reach = far.norm();
  const double scale = std::max({1.0, apex.cwiseAbs().maxCoeff(), lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff(),
                                 std::abs(plane_x)}) + reach;
  const double margin = 1e-9 + 1e-12 * scale * (1.0 + 4.0 * reach / d_min);
  for (int axis = 0; axis < 2; ++axis) {
    const int a = axis == 0 ? g.axis_u : g.axis_v;
    const double n_lo = lo[a] - apex[a], n_hi = hi[a] - apex[a];
    const double q[4] = {d_apex * n_lo / d_lo, d_apex * n_lo / d_hi, d_apex * n_hi / d_lo, d_apex * n_hi / d_hi};
    region[axis][0] = apex[a] + *std::min_element(q, q + 4) - margin;
    region[axis][1] = apex[a] + *std::max_element(q, q + 4) + margin;
    if (!std::isfinite(region[axis][0]) || !std::isfinite(region[axis][1])) return false;
  }
  if (margin_m) *margin_m = margin;
  if (amplification) *amplification = reach / d_min;
  return std::isfinite(margin);
}

bool PathFinder::any_occupied(const PlaneGroup& g, const double region[2][2]) const {
  // cell_bit's grid: [u0, u0 + nu / inv_du) × [v0, v0 + nv / inv_dv); a point outside it is rejected.
  const double u1 = g.u0 + g.nu / g.inv_du, v1 = g.v0 + g.nv / g.inv_dv;
  const auto beyond = [](double x, double end) { return x > end + 1e-9 * (std::abs(end) + 1.0); };
  if (region[0][1] < g.u0 || region[1][1] < g.v0 || beyond(region[0][0], u1) || beyond(region[1][0], v1)) return false;
  const auto cell = [](double x, double x0, double inv, int n) {
    return static_cast<int>(std::clamp(std::floor((x - x0) * inv), 0.0, n - 1.0));
  };
  const int iu0 = cell(region[0][0], g.u0, g.inv_du, g.nu), iu1 = cell(region[0][1], g.u0, g.inv_du, g.nu);
  const int iv0 = cell(region[1][0], g.v0, g.inv_dv, g.nv), iv1 = cell(region[1][1], g.v0, g.inv_dv, g.nv);
  return any_bit_in_rect(occupancy_, g.bit_offset, g.nu, iu0, iu1, iv0, iv1);
}

// try_plane_pair rejects a link unless P2 (on plane 2) and P1 (on plane 1) lie on occupied cells. Geometrically
// (the unfolded path A → P1 → P2 → T is straight from A1, A's image in plane 1, to T2, T's image in plane 2):
// P2 is the reflection point between A1 and T in plane 2, and P1 the reflection point between A and P2 in
// plane 1, each apex strictly on the side of its box. So per pair: the window of P2 over the tag box, then
// the window of P1 over that window (a flat box on plane 2, widened by its margin); a pair with either
// window off its grid or on empty cells carries no path for any tag of the box. Where a window cannot be
// bounded (a plane not axis-aligned, an apex or box not strictly on one side) the pair is kept.
void PathFinder::plane_pairs_near(const Vec3& a, const Vec3& lo, const Vec3& hi, std::vector<PlanePair>& out) const {
  out.clear();
  const auto n = static_cast<uint32_t>(planes_.size());
  for (uint32_t g1 = 0; g1 < n; ++g1) {
    const PlaneGroup& first = planes_[g1];
    Vec3 a1 = a;
    if (first.axis_sign != 0) a1[first.axis_k] = 2.0 * first.axis_sign * first.offset_m - a[first.axis_k];
    for (uint32_t g2 = 0; g2 < n; ++g2) {
      if (g1 == g2) continue;
      const PlaneGroup& second = planes_[g2];
      double w2[2][2], w1[2][2], margin2 = 0.0;
      if (first.axis_sign != 0 && reflection_window(second, a1, lo, hi, w2, &margin2)) {
        if (!any_occupied(second, w2)) continue;
        // The window of P2 as a flat box on plane 2, as thick as the window's rounding margin.
        Vec3 box_lo, box_hi;
        box_lo[second.axis_u] = w2[0][0], box_hi[second.axis_u] = w2[0][1];
        box_lo[second.axis_v] = w2[1][0], box_hi[second.axis_v] = w2[1][1];
        const double x2 = second.axis_sign * second.offset_m;
        box_lo[second.axis_k] = x2 - margin2, box_hi[second.axis_k] = x2 + margin2;
        // P2's own rounding grows with P1's, which grows as 1 / cos of the first incidence (≤ amplification):
        // the margins hold up to 10³ (incidence 89.94° from the normal); closer to grazing the pair is kept.
        double amplification = 0.0;
        if (reflection_window(first, a, box_lo, box_hi, w1, nullptr, &amplification) && amplification < 1e3 &&
            !any_occupied(first, w1))
          continue;
      }
      out.push_back({g1, g2});
    }
  }
}

}  // namespace rfidray
