// Levels full-selective and full: second-order diffraction at two edges (raytrace/edge_pairs.h: parallel edges, and
// any two edges of one facet), the path A → Q1 (edge 1) → Q2 (edge 2) → T, the leg Q1 → Q2 between λ/2 (UTD at
// edge 2 takes edge 1's field there for a ray) and TraceOptions::double_diffraction_max_m. Why: between the two plates
// of a rack bay first-order UTD lights each plate's back edge with the free-space field and the plate's full
// reflection, but the back edge lies in the front edge's transition region (a ray grazing the plate at 7–11°, its
// first Fresnel zone along the plate metres long): the field that reaches it is the front edge's incident and
// reflected fields plus that edge's diffracted field, which only this path carries. Against FDTD (docs/fullwave.md):
// the rack bay's median error 0.128 → 0.074, a link grazing a plate's corner 0.61–0.94 → 0.05–0.17.
//
// Geometry: Keller's law at both edges (each edge's two legs at equal angles to it) is Fermat's principle, the length
// L(t1, t2) = |Q1 − A| + |Q2 − Q1| + |T − Q2| stationary in the two points' positions along their edges. L is convex
// (a sum of norms of affine maps), so its stationary point is its minimum: for parallel edges in closed form (every
// leg at one angle to them, the unfolded path straight: with ρ0, ρ12, ρ2 the distances across the edges' direction
// and z along it, z_Q1 = z_A + (z_T − z_A)·ρ0/(ρ0 + ρ12 + ρ2), z_Q2 = z_A + (z_T − z_A)·(ρ0 + ρ12)/(ρ0 + ρ12 + ρ2)),
// otherwise by Newton's method on the 2 × 2 system, after two exact tests that reject most pairs of most links in
// closed form (path_points_on_edges, corner_view_is_shortest). A point off its edge: no path.
// Field (KP's spherical-wave diffraction twice): edge 1's diffracted wave at Q2 is astigmatic, radius ρ1 = s12 across
// edge 1 (its caustic is the edge) and ρ2 = s' + s12 along it; edge 2 sees it with the radius ρe of its normal section
// in edge 2's plane of incidence (1/ρe = cos²θ/ρ1 + sin²θ/ρ2, θ between that section and edge 1's φ̂), and a
// straight edge's diffracted wave keeps ρe as its caustic distance (KP eq. 16 with no edge curvature):
//   E = E_A(ŝ') · e^{−jkL} · D1 · D2 · (1/s')·√(s'/(s12(s' + s12))) · √(ρe/(s(ρe + s))),  L = s' + s12 + s,
// with D1 for source A and observer Q2 (L1 = s' s12 sin²β1/(s' + s12)) and D2 for that wave (KP's general
// L2 = s(ρe + s)ρ1ρ2 sin²β2/(ρe(ρ1 + s)(ρ2 + s))), each a dyadic in its own edge-fixed basis
// (raytrace/diffraction.cpp). For parallel edges ρe = ρ2 and the amplitude is √(L/(s' s12 s))/L.
// When the two edges bound one facet the leg between them runs along it (grazing): edge 1's field along the face is
// its diffracted field at φ = 0 (or nπ), and edge 2's hard coefficient at grazing incidence is halved, since its two
// terms then count one field twice (Kouyoumjian & Pathak, Proc. IEEE 62(11), 1974, the note after eq. 31). Both sides
// of a sheet carry such a leg (a half-plane's two faces); a solid's edge only its outside. The soft coefficient
// vanishes at grazing (the field along a conductor's face with E along the edge is zero): slope diffraction, which
// would carry that case, is not modelled.
// Not modelled: more than two diffractions (a path whose last leg grazes a face, e.g. in a plate's plane beyond its
// edge, needs a third to be continuous), diffraction combined with reflection, non-parallel edges of different
// facets, and whether a leg across a non-convex facet stays on it.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <vector>

#include "core/fresnel.h"
#include "core/units.h"
#include "core/utd.h"
#include "raytrace/line_feet.h"
#include "raytrace/path_finder.h"

namespace rfidray {
namespace {

constexpr double kDoubleDiffractionOnEdgeM = 1e-6;  // an end this close to an edge's line is on it
// The span test's slack (double_diffractions), shared by edge_pairs_near's bound of it.
constexpr double kSpanSlackM = 1e-4;

// The wedge angles about edge e of a grazing leg, along the face that `into_face` points into (⟂ the edge) on the
// side `side` (that face's normal or its opposite), and of the other end `v_other` (⟂ the edge); the grazing leg is
// the source (φ') or the observer (φ) as `graze_is_source` says, its angle snapped to 0 or nπ. False when the other
// end is not in the exterior region on that side.
bool grazing_angles(const Edge& e, const Vec3& into_face, const Vec3& side, const Vec3& v_other, bool graze_is_source,
                    WedgeAngles& w) {
  const Vec3 v_graze = into_face + 1e-6 * side;  // just off the face on that side: which region it is in
  const bool ok = graze_is_source ? wedge_angles(e, v_graze, v_other, w) : wedge_angles(e, v_other, v_graze, w);
  if (!ok) return false;
  double& a = graze_is_source ? w.phi_prime_rad : w.phi_rad;
  a = a < 0.5 * w.n * kPi ? 0.0 : w.n * kPi;
  return true;
}

double sq(double x) { return x * x; }

// The cone of directions from a point p to a ball (edge_pairs_near): its axis and half-angle, padded by 1e-7 rad for
// acos's and asin's rounding near 0 and π; unbounded when the ball reaches p.
struct ConeToBall {
  Vec3 axis = Vec3::Zero();
  double half_angle_rad = 0.0;
  bool bounded = false;
};
ConeToBall cone_to_ball(const Vec3& p, const Vec3& centre, double radius) {
  ConeToBall cone;
  const Vec3 pm = centre - p;
  const double distance = pm.norm();
  cone.bounded = distance > 1.001 * radius;
  if (cone.bounded) {
    cone.axis = pm / distance;
    cone.half_angle_rad = std::asin(radius / distance) + 1e-7;
  }
  return cone;
}
// The interval of d·u over the unit vectors u of a bounded cone (the cosines of d's angles to it), widened by 1e-9.
void cosine_range(const ConeToBall& cone, const Vec3& d, double& lo_cos, double& hi_cos) {
  const double theta = std::acos(std::clamp(d.dot(cone.axis), -1.0, 1.0));
  hi_cos = std::cos(std::max(0.0, theta - cone.half_angle_rad)) + 1e-9;
  lo_cos = std::cos(std::min(kPi, theta + cone.half_angle_rad)) - 1e-9;
}

// A corner of a pair of edges seen from the link's ends: the unit vectors (C − A)/|C − A| and (T − C)/|T − C|.
struct CornerView {
  Vec3 from_a = Vec3::Zero(), to_t = Vec3::Zero();
  bool on_corner = false;  // A or T within 1e-12 m of C
};

// Two edges that meet at a corner C (not parallel): whether the shortest path A → edge 1 → edge 2 → T is the one
// through C itself, where the middle leg vanishes. L is convex, so that is when 0 is in its subdifferential at C:
// some z with |z| ≤ 1 (the subgradients of |Q2 − Q1| at 0) has d1·z = d1·(C − A)/|C − A| and d2·z = d2·(T − C)/|T − C|;
// the shortest such z lies in the plane of d1 and d2. Exact, and cheap where Newton's method would crawl to the kink.
// `v`: C seen from this link's A and T.
bool corner_view_is_shortest(const Edge& e1, const Edge& e2, const CornerView& v) {
  if (v.on_corner) return true;
  const double p = e1.direction.dot(v.from_a), q = e2.direction.dot(v.to_t);
  const double c = e1.direction.dot(e2.direction);
  const double alpha = (p - c * q) / (1.0 - c * c), beta = (q - c * p) / (1.0 - c * c);
  return alpha * p + beta * q <= 1.0;
}

// The corner where edges e1 and e2 meet, as e1's end point (the point the corner test measures from), or false.
bool meeting_corner(const Edge& e1, const Edge& e2, Vec3& corner) {
  const Vec3 ends1[2] = {e1.start, e1.start + e1.length_m * e1.direction};
  const Vec3 ends2[2] = {e2.start, e2.start + e2.length_m * e2.direction};
  for (const Vec3& c1 : ends1)
    for (const Vec3& c2 : ends2)
      if ((c1 - c2).squaredNorm() <= 1e-18) {
        corner = c1;
        return true;
      }
  return false;
}

// The Fermat point of a path F → line → P on a line (origin o, unit direction d): its coordinate along the line,
// dividing [z_F, z_P] in the ratio ρ_F : ρ_P of the two points' distances from it (unclamped; NaN if both are on it).
double fermat_on_line(const Vec3& o, const Vec3& d, const Vec3& f, const Vec3& p) {
  const Vec3 rf = f - o, rp = p - o;
  const double zf = rf.dot(d), zp = rp.dot(d);
  const double rho_f = (rf - zf * d).norm(), rho_p = (rp - zp * d).norm();
  return zf + (zp - zf) * rho_f / (rho_f + rho_p);
}

// Whether the shortest path A → edge 1 → edge 2 → T over the two edges' whole lines has both points on the edges,
// without finding it. h(t2) = min over t1 of L(t1, t2) is convex (L is jointly convex), its minimizer is the path's
// t2, and by the envelope theorem h'(t2) = ∂L/∂t2 at t1 = the Fermat point on line 1 of A and Q2(t2), in closed
// form. So t2 ∈ [0, len2] exactly when h' ≤ 0 at 0 and ≥ 0 at len2; likewise t1. Four closed-form evaluations
// that reject, exactly, the pairs whose path is off an edge (most pairs, most links) before Newton's method.
bool path_points_on_edges(const Edge& e1, const Edge& e2, const Vec3& a, const Vec3& t) {
  const Vec3 &d1 = e1.direction, &d2 = e2.direction;
  const auto g1 = [&](double t1, double t2) {  // ∂L/∂t1 = d1·(û − v̂)
    const Vec3 q1 = e1.start + t1 * d1, q2 = e2.start + t2 * d2;
    return d1.dot((q1 - a).normalized() - (q2 - q1).normalized());
  };
  const auto g2 = [&](double t1, double t2) {  // ∂L/∂t2 = d2·(v̂ − ŵ)
    const Vec3 q1 = e1.start + t1 * d1, q2 = e2.start + t2 * d2;
    return d2.dot((q2 - q1).normalized() - (t - q2).normalized());
  };
  for (double t2 : {0.0, e2.length_m}) {
    const double t1 = fermat_on_line(e1.start, d1, a, e2.start + t2 * d2);
    if (!std::isfinite(t1)) return true;  // degenerate: let Newton's method decide
    const double slope = g2(t1, t2);
    if (t2 == 0.0 ? slope > 0.0 : slope < 0.0) return false;
  }
  for (double t1 : {0.0, e1.length_m}) {
    const double t2 = fermat_on_line(e2.start, d2, t, e1.start + t1 * d1);
    if (!std::isfinite(t2)) return true;
    const double slope = g1(t1, t2);
    if (t1 == 0.0 ? slope > 0.0 : slope < 0.0) return false;
  }
  return true;
}

// The two diffraction points of edges e1, e2 (not parallel) for A and T: the minimum of the path's length over
// their positions t1, t2 along the edges, by Newton's method with a backtracking line search (L is convex). False
// when it does not converge, a point falls off its edge, or the leg between them falls below `min_leg_m`.
bool keller_points(const Edge& e1, const Edge& e2, const Vec3& a, const Vec3& t, double min_leg_m, double& t1,
                   double& t2) {
  const Vec3 &d1 = e1.direction, &d2 = e2.direction;
  const auto length = [&](double x1, double x2) {
    const Vec3 q1 = e1.start + x1 * d1, q2 = e2.start + x2 * d2;
    return (q1 - a).norm() + (q2 - q1).norm() + (t - q2).norm();
  };
  t1 = 0.5 * e1.length_m;
  t2 = 0.5 * e2.length_m;
  double l = length(t1, t2);
  for (int iteration = 0; iteration < 60; ++iteration) {
    const Vec3 q1 = e1.start + t1 * d1, q2 = e2.start + t2 * d2;
    const Vec3 u = q1 - a, v = q2 - q1, w = t - q2;
    const double nu = u.norm(), nv = v.norm(), nw = w.norm();
    // The middle leg shrinking to nothing: the minimum is the kink where the two edges meet (a corner, which
    // diffracts as a corner, not modelled), where L is not differentiable and Newton would crawl.
    if (!(nu > 1e-12 && nv > min_leg_m && nw > 1e-12)) return false;
    const Vec3 uh = u / nu, vh = v / nv, wh = w / nw;
    const double g1 = d1.dot(uh - vh), g2 = d2.dot(vh - wh);
    if (std::abs(g1) < 1e-13 && std::abs(g2) < 1e-13) break;
    const double h11 = (1.0 - sq(d1.dot(uh))) / nu + (1.0 - sq(d1.dot(vh))) / nv;
    const double h22 = (1.0 - sq(d2.dot(vh))) / nv + (1.0 - sq(d2.dot(wh))) / nw;
    const double h12 = -(d1.dot(d2) - d1.dot(vh) * d2.dot(vh)) / nv;
    const double det = h11 * h22 - h12 * h12;
    if (!(det > 1e-300)) return false;
    double step1 = -(h22 * g1 - h12 * g2) / det, step2 = -(h11 * g2 - h12 * g1) / det;
    // Backtrack until the length decreases (Newton's step on a convex function is a descent direction).
    double scale = 1.0, next = length(t1 + step1, t2 + step2);
    while (next > l && scale > 1e-9) {
      scale *= 0.5;
      next = length(t1 + scale * step1, t2 + scale * step2);
    }
    t1 += scale * step1;
    t2 += scale * step2;
    if (std::abs(scale * step1) < 1e-13 && std::abs(scale * step2) < 1e-13) break;
    l = next;
  }
  const Vec3 q1 = e1.start + t1 * d1, q2 = e2.start + t2 * d2;
  const double g1 = d1.dot((q1 - a).normalized() - (q2 - q1).normalized());
  const double g2 = d2.dot((q2 - q1).normalized() - (t - q2).normalized());
  if (!(std::abs(g1) < 1e-9 && std::abs(g2) < 1e-9)) return false;
  return t1 >= 0.0 && t1 <= e1.length_m && t2 >= 0.0 && t2 <= e2.length_m;
}

}  // namespace

void PathFinder::index_edge_pairs() {
  std::vector<uint8_t> paired(edges_.size(), 0);
  for (const EdgePair& p : edge_pairs_) paired[p.first] = paired[p.second] = 1;
  paired_edges_.clear();
  max_edge_coordinate_m_ = 0.0;
  for (uint32_t i = 0; i < edges_.size(); ++i) {
    if (!paired[i]) continue;
    paired_edges_.push_back(i);
    const Edge& e = edges_[i];
    max_edge_coordinate_m_ = std::max({max_edge_coordinate_m_, e.start.cwiseAbs().maxCoeff(),
                                       (e.start + e.length_m * e.direction).cwiseAbs().maxCoeff()});
  }
  pair_corners_.clear();
  pair_corner_of_.assign(2 * edge_pairs_.size(), -1);
  std::map<std::array<double, 3>, int32_t> index;  // exact coordinates → corner
  for (size_t pi = 0; pi < edge_pairs_.size(); ++pi) {
    const EdgePair& pair = edge_pairs_[pi];
    if (pair.parallel || pair.distance_m != 0.0) continue;
    for (int order = 0; order < 2; ++order) {
      const Edge& e1 = edges_[order == 0 ? pair.first : pair.second];
      const Edge& e2 = edges_[order == 0 ? pair.second : pair.first];
      Vec3 corner;
      if (!meeting_corner(e1, e2, corner)) continue;  // touching elsewhere: no corner test
      // The same point (to the bit) for every pair meeting there: one view per corner and link.
      const auto [at, added] = index.try_emplace({corner.x(), corner.y(), corner.z()},
                                                 static_cast<int32_t>(pair_corners_.size()));
      if (added) pair_corners_.push_back(corner);
      pair_corner_of_[2 * pi + order] = at->second;
    }
  }
}

// What double_diffractions' per-link tests decide, bounded over a box of tags (the block's), with A fixed. Every bound
// is a superset of what the per-link test passes for any tag T in the box, widened by `margin` (1e-9 of the scene's
// scale: the per-link arithmetic rounds by a few ulps of its coordinates, 10⁵ times less), so a pruned order is one
// the per-link loop would have rejected for every tag of the block, and the kept ones are walked in the same order:
// the same paths (tests/raytrace/test_edge_pair_sharing.cpp). The box is taken as its bounding ball (centre m,
// radius r), and what a tag sees from a line is 1-Lipschitz in T: its coordinate along the line and its distance
// from it move by at most |T − m| ≤ r.
//  - Parallel pairs: the span test (both edges overlap [min(z_A, z_T), max(z_A, z_T)], over z_T's interval), then the
//    Fermat points z_Q1 = z_A + (z_T − z_A)·w1, w1 = ρ0/(ρ0 + ρ12 + ρ2), and z_Q2 likewise with w2 = (ρ0 + ρ12)/(…):
//    bilinear in (z_T, w) over a rectangle, so bounded by its four corners; ρ2 (T from edge 2's line) in [ρc − r, ρc + r].
//  - Pairs meeting at a corner C: rejected when the shortest path is through C, i.e. f(q) = (p² − 2cpq + q²)/(1 − c²)
//    ≤ 1 (corner_view_is_shortest), p = d1·(C − A)/|C − A| fixed, q = d2·(T − C)/|T − C|. f is convex in q, so f ≤ 1 at
//    both ends of q's interval (the cosines of d2's angles to the cone of directions from C to the ball) rejects
//    every tag; kept when 1 − c² < 1e-3 (near-parallel edges, where rounding in f grows as 1/(1 − c²)) or the ball
//    reaches C.
//  - Every pair not parallel: the antenna's half of the slope test (path_points_on_edges at t2 = 0 and len2, where the
//    Fermat point on edge 1 does not depend on T), whose one tag-dependent term is a cosine over the cone from edge 2's
//    end to the ball (below, slope_rejects_box).
void PathFinder::edge_pairs_near(const Vec3& a, const Vec3& lo, const Vec3& hi, EdgePairBlock& out) const {
  out.orders.clear();
  out.edges.clear();
  out.corners.clear();
  if (edge_pairs_.empty()) return;
  const Vec3 m = 0.5 * (lo + hi);
  const double scale = std::max({1.0, a.cwiseAbs().maxCoeff(), lo.cwiseAbs().maxCoeff(), hi.cwiseAbs().maxCoeff(),
                                 max_edge_coordinate_m_});
  const double margin = 1e-9 * scale;
  const double r = 0.5 * (hi - lo).norm() + margin;
  // Per paired edge: A's feet (as per link) and the box centre's, T's coordinate along the line in [z_c − r, z_c + r].
  thread_local std::vector<LineFeet> tl_box_feet;
  thread_local std::vector<uint8_t> tl_box_span, tl_edge_used;
  tl_box_feet.resize(edges_.size());
  tl_box_span.resize(edges_.size());
  tl_edge_used.assign(edges_.size(), 0);
  for (const uint32_t ei : paired_edges_) {
    const LineFeet& feet = tl_box_feet[ei] = line_feet(edges_[ei].start, edges_[ei].direction, a, m);
    tl_box_span[ei] = std::max(feet.z_a, feet.z_t + r) >= -kSpanSlackM - margin &&
                      std::min(feet.z_a, feet.z_t - r) <= edges_[ei].length_m + kSpanSlackM + margin;
  }
  // Per corner: C's direction from A (as per link; A on C rejects every tag), and the cone from C to the ball.
  struct CornerCone {
    Vec3 from_a = Vec3::Zero();
    bool a_on_corner = false;
    ConeToBall to_ball;
  };
  thread_local std::vector<CornerCone> tl_cones;
  thread_local std::vector<uint8_t> tl_corner_used;
  tl_cones.resize(pair_corners_.size());
  tl_corner_used.assign(pair_corners_.size(), 0);
  for (size_t c = 0; c < pair_corners_.size(); ++c) {
    CornerCone& cone = tl_cones[c];
    const Vec3 ca = pair_corners_[c] - a;
    const double ca_norm = ca.norm();
    cone.a_on_corner = ca_norm < 1e-12;
    if (!cone.a_on_corner) cone.from_a = ca / ca_norm;
    cone.to_ball = cone_to_ball(pair_corners_[c], m, r);
  }
  // Per edge taken second, at its start and its end: the interval of d2·(T − end)/|T − end| (computed when first
  // needed in this block; 0: not yet, 1: bounded, 2: unbounded).
  struct EndCosines {
    double lo[2] = {0.0, 0.0}, hi[2] = {0.0, 0.0};
    uint8_t state[2] = {0, 0};
  };
  thread_local std::vector<EndCosines> tl_end_cosines;
  tl_end_cosines.resize(edges_.size());
  for (const uint32_t ei : paired_edges_) tl_end_cosines[ei].state[0] = tl_end_cosines[ei].state[1] = 0;
  // path_points_on_edges' first half: at t2 = 0 and t2 = len2, t1 is the Fermat point on line 1 of A and Q2, which
  // does not depend on T, and the slope there, d2·(v̂ − ŵ) with v̂ = (Q2 − Q1)/|Q2 − Q1| and ŵ = (T − Q2)/|T − Q2|,
  // rejects the link when positive at 0 or negative at len2: for every tag of the box when d2·ŵ's interval says so.
  // The same arithmetic as per link for v̂; a non-finite t1 keeps the order, as per link.
  const auto slope_rejects_box = [&](size_t pi, int order) {
    const EdgePair& pair = edge_pairs_[pi];
    const uint32_t i1 = order == 0 ? pair.first : pair.second, i2 = order == 0 ? pair.second : pair.first;
    const Edge& e1 = edges_[i1];
    const Edge& e2 = edges_[i2];
    const Vec3 &d1 = e1.direction, &d2 = e2.direction;
    EndCosines& ends = tl_end_cosines[i2];
    for (int end = 0; end < 2; ++end) {
      const double t2 = end == 0 ? 0.0 : e2.length_m;
      const Vec3 q2 = e2.start + t2 * d2;
      const double t1 = fermat_on_line(e1.start, d1, a, q2);
      if (!std::isfinite(t1)) return false;
      if (ends.state[end] == 0) {
        const ConeToBall cone = cone_to_ball(q2, m, r);
        if (cone.bounded) cosine_range(cone, d2, ends.lo[end], ends.hi[end]);
        ends.state[end] = cone.bounded ? 1 : 2;
      }
      if (ends.state[end] != 1) continue;
      const Vec3 q1 = e1.start + t1 * d1;
      const double dv = d2.dot((q2 - q1).normalized());
      if (end == 0 ? dv - ends.hi[0] > 1e-9 : dv - ends.lo[1] < -1e-9) return true;
    }
    return false;
  };
  const auto keep = [&](size_t pi, int order) {
    out.orders.push_back(static_cast<uint32_t>(2 * pi + order));
    tl_edge_used[edge_pairs_[pi].first] = tl_edge_used[edge_pairs_[pi].second] = 1;
    const int32_t corner = pair_corner_of_[2 * pi + order];
    if (corner >= 0) tl_corner_used[corner] = 1;
  };
  for (size_t pi = 0; pi < edge_pairs_.size(); ++pi) {
    const EdgePair& pair = edge_pairs_[pi];
    if (pair.parallel && !(tl_box_span[pair.first] && tl_box_span[pair.second])) continue;
    for (int order = 0; order < 2; ++order) {
      const uint32_t i1 = order == 0 ? pair.first : pair.second, i2 = order == 0 ? pair.second : pair.first;
      const Edge& e1 = edges_[i1];
      const Edge& e2 = edges_[i2];
      if (pair.parallel) {
        const LineFeet& feet = tl_box_feet[i1];
        const double za = feet.z_a, rho0 = feet.rho_a, rho12 = pair.offset_length_m[order];
        const double rho_c = (feet.v_t - pair.offset_m[order]).norm();
        const double rho2_lo = std::max(0.0, rho_c - r), rho2_hi = rho_c + r;
        const double zt_lo = feet.z_t - r, zt_hi = feet.z_t + r;
        // The interval of z_A + (z_T − z_A)·w over z_T ∈ [zt_lo, zt_hi], w ∈ [w_lo, w_hi].
        const auto range = [&](double numerator, double out_lo_hi[2]) {
          const double w_lo = numerator / (rho0 + rho12 + rho2_hi), w_hi = numerator / (rho0 + rho12 + rho2_lo);
          const double c[4] = {za + (zt_lo - za) * w_lo, za + (zt_lo - za) * w_hi, za + (zt_hi - za) * w_lo,
                               za + (zt_hi - za) * w_hi};
          out_lo_hi[0] = *std::min_element(c, c + 4) - margin;
          out_lo_hi[1] = *std::max_element(c, c + 4) + margin;
        };
        if (rho0 + rho12 + rho2_lo > 0.0) {
          double zq1[2], zq2[2];
          range(rho0, zq1);
          if (zq1[1] < 0.0 || zq1[0] > e1.length_m) continue;
          range(rho0 + rho12, zq2);
          // Q2 = e1.start + w12 + z_Q2·d1, its coordinate along edge 2: c0 + c1·z_Q2.
          const double c0 = (e1.start + pair.offset_m[order] - e2.start).dot(e2.direction);
          const double c1 = e1.direction.dot(e2.direction);
          const double x1 = c0 + c1 * zq2[0], x2 = c0 + c1 * zq2[1];
          if (std::max(x1, x2) + margin < 0.0 || std::min(x1, x2) - margin > e2.length_m) continue;
        }
      } else {
        const int32_t corner = pair_corner_of_[2 * pi + order];
        if (corner >= 0) {
          const CornerCone& cone = tl_cones[corner];
          if (cone.a_on_corner) continue;  // on_corner for every tag: rejected
          const double c = e1.direction.dot(e2.direction);
          if (cone.to_ball.bounded && 1.0 - c * c >= 1e-3) {
            const double p = e1.direction.dot(cone.from_a);
            double q_lo = 0.0, q_hi = 0.0;
            cosine_range(cone.to_ball, e2.direction, q_lo, q_hi);
            const auto f_of = [&](double q) { return (p * p - 2.0 * c * p * q + q * q) / (1.0 - c * c); };
            if (std::max(f_of(q_lo), f_of(q_hi)) <= 1.0 - 1e-6) continue;
          }
        }
        if (slope_rejects_box(pi, order)) continue;
      }
      keep(pi, order);
    }
  }
  for (const uint32_t ei : paired_edges_)
    if (tl_edge_used[ei]) out.edges.push_back(ei);
  for (size_t c = 0; c < pair_corners_.size(); ++c)
    if (tl_corner_used[c]) out.corners.push_back(static_cast<uint32_t>(c));
}

void PathFinder::double_diffractions(const Endpoint& ant, const Endpoint& tag, double f, double floor,
                                     const EdgePairBlock* block, std::vector<TracedPath>& out) const {
  if (edge_pairs_.empty()) return;
  const Vec3& a = ant.pose.position;
  const Vec3& t = tag.pose.position;
  const double k = wavenumber_rad_m(f);
  const auto& facets = scene_->facets();
  const auto& materials = scene_->materials();
  const EmbreeScene& bvh = scene_->bvh();
  using C = std::complex<double>;
  const double min_leg_m = 0.5 * wavelength_m(f);
  // A and T seen from every paired edge's line (or every edge the block's orders read), once per link instead of
  // once per pair and order (an edge is in many pairs). Per-thread scratch: no allocation once warm.
  //
  // Across two parallel edges both diffraction points lie between A's and T's feet on each edge's line (Fermat:
  // the unfolded path is straight), so a pair whose either edge lies wholly beyond both feet has no path (most
  // pairs of most links). The slack keeps this a superset of the exact test below: float rounding of the points
  // (~1e-14 m) and the 1e-6 rad that "parallel" allows (≤ 1e-6 m over a 1 m gap).
  thread_local std::vector<LineFeet> tl_feet;
  thread_local std::vector<uint8_t> tl_span;  // 1: the edge overlaps [min(z_A, z_T), max(z_A, z_T)] along its line
  tl_feet.resize(edges_.size());
  tl_span.resize(edges_.size());
  for (const uint32_t ei : block ? std::span<const uint32_t>(block->edges) : std::span<const uint32_t>(paired_edges_)) {
    const LineFeet& feet = tl_feet[ei] = line_feet(edges_[ei].start, edges_[ei].direction, a, t);
    tl_span[ei] = std::max(feet.z_a, feet.z_t) >= -kSpanSlackM &&
                  std::min(feet.z_a, feet.z_t) <= edges_[ei].length_m + kSpanSlackM;
  }
  // The corners' directions from A and to T, once per link and corner (shared by every pair meeting there).
  thread_local std::vector<CornerView> tl_corners;
  tl_corners.resize(pair_corners_.size());
  const auto view_corner = [&](size_t c) {
    const Vec3 ca = pair_corners_[c] - a, tc = t - pair_corners_[c];
    CornerView& v = tl_corners[c];
    const double ca_norm = ca.norm(), tc_norm = tc.norm();
    v.on_corner = ca_norm < 1e-12 || tc_norm < 1e-12;
    if (!v.on_corner) v.from_a = ca / ca_norm, v.to_t = tc / tc_norm;
  };
  if (block) {
    for (const uint32_t c : block->corners) view_corner(c);
  } else {
    for (size_t c = 0; c < pair_corners_.size(); ++c) view_corner(c);
  }
  // Every order of every pair (2·pair + order), or the orders edge_pairs_near kept for this link's block (ascending:
  // the same paths in the same order).
  const size_t orders = block ? block->orders.size() : 2 * edge_pairs_.size();
  tl_edge_pair_orders_tried += orders;
  for (size_t i = 0; i < orders; ++i) {  // pairs found within double_diffraction_max_m (edge_pairs.h)
    const uint32_t o = block ? block->orders[i] : static_cast<uint32_t>(i);
    const size_t pi = o >> 1;
    const int order = static_cast<int>(o & 1u);
    const EdgePair& pair = edge_pairs_[pi];
    if (pair.parallel && !(tl_span[pair.first] && tl_span[pair.second])) {
      if (!block) i |= 1u;  // the pair's other order fails it too: on to the next pair
      continue;
    }
    // One order of the pair (edge 1 first, then edge 2): the exact tests, the field, the legs.
    const uint32_t i1 = order == 0 ? pair.first : pair.second, i2 = order == 0 ? pair.second : pair.first;
    const Edge& e1 = edges_[i1];
    const Edge& e2 = edges_[i2];
    const Vec3& d = e1.direction;
    const LineFeet& feet1 = tl_feet[i1];
    Vec3 q1, q2, va, vt2;  // va: A from edge 1's line; vt2: T from edge 2's line (both ⟂ their edge)
    if (pair.parallel) {
      // Across the edges: A from edge 1's line, edge 2's line from edge 1's, T from edge 2's line.
      const double za = feet1.z_a, zt = feet1.z_t;
      va = feet1.v_a;
      const Vec3& w12 = pair.offset_m[order];
      vt2 = feet1.v_t - w12;
      const double rho0 = feet1.rho_a, rho12 = pair.offset_length_m[order], rho2 = vt2.norm();
      if (rho0 < kDoubleDiffractionOnEdgeM || rho2 < kDoubleDiffractionOnEdgeM) continue;
      const double total = rho0 + rho12 + rho2;
      const double zq1 = za + (zt - za) * rho0 / total, zq2 = za + (zt - za) * (rho0 + rho12) / total;
      if (zq1 < 0.0 || zq1 > e1.length_m) continue;
      q1 = e1.start + zq1 * d;
      q2 = e1.start + w12 + zq2 * d;
      const double along2 = (q2 - e2.start).dot(e2.direction);
      if (along2 < 0.0 || along2 > e2.length_m) continue;
    } else {
      va = feet1.v_a;
      vt2 = tl_feet[i2].v_t;
      if (feet1.rho_a < kDoubleDiffractionOnEdgeM || tl_feet[i2].rho_t < kDoubleDiffractionOnEdgeM) continue;
      // Both tests are exact; the corner's (two square roots) first: it rejects most corner pairs (paper
      // warehouse: it leaves 5 % of what the slope test leaves), the slope test's sixteen are then mostly spared.
      const int32_t corner = pair_corner_of_[2 * pi + order];
      if (corner >= 0 && corner_view_is_shortest(e1, e2, tl_corners[corner])) continue;
      if (!path_points_on_edges(e1, e2, a, t)) continue;
      double t1 = 0.0, t2 = 0.0;
      if (!keller_points(e1, e2, a, t, 0.1 * min_leg_m, t1, t2)) continue;
      q1 = e1.start + t1 * d;
      q2 = e2.start + t2 * e2.direction;
    }
    const Vec3 s1 = q1 - a, s12v = q2 - q1, s2 = t - q2;
    const double s_in = s1.norm(), s12 = s12v.norm(), s_out = s2.norm();
    if (!(s_in > 0.0 && s12 > 0.0 && s_out > 0.0)) continue;
    // The leg between the edges: at most double_diffraction_max_m, and at least λ/2 (k·s12 ≥ π): UTD at edge 2
    // takes edge 1's diffracted field there for a ray. Closer edges (a 3 cm shelf's two front edges) are one thick
    // edge, which this does not model.
    if (s12 > options_.double_diffraction_max_m || s12 < min_leg_m) continue;
    const double length = s_in + s12 + s_out;
    if (length * length > max_length2_) continue;
    const Vec3 s_hat_in = s1 / s_in, s_hat_mid = s12v / s12, s_hat_out = s2 / s_out;
    const double sin_beta1 = s_hat_in.cross(d).norm(), sin_beta2 = s_hat_mid.cross(e2.direction).norm();
    if (sin_beta1 < 1e-9 || sin_beta2 < 1e-9) continue;
    const double beta1 = std::atan2(sin_beta1, s_hat_in.dot(d));
    const double beta2 = std::atan2(sin_beta2, s_hat_mid.dot(e2.direction));
    // The leg between the edges, across each edge (from edge 1 into its side; from edge 2 back to edge 1).
    const Vec3 w1 = s12v - s12v.dot(d) * d, w2 = -(s12v - s12v.dot(e2.direction) * e2.direction);
    if (w1.norm() < kDoubleDiffractionOnEdgeM || w2.norm() < kDoubleDiffractionOnEdgeM) continue;
    const Vec3 u1 = w1.normalized(), u2 = w2.normalized();
    // One leg between the edges in free space, or one per side of their shared face (a sheet's two sides).
    const Vec3 face_normal = pair.shared_facet != kNoFacet ? facets[pair.shared_facet].normal : Vec3::Zero();
    const int sides = pair.shared_facet != kNoFacet ? 2 : 1;
    for (int side_index = 0; side_index < sides; ++side_index) {
      const Vec3 side = side_index == 0 ? face_normal : Vec3(-face_normal);
      WedgeAngles wa1, wa2;
      const bool grazing = pair.shared_facet != kNoFacet;
      if (grazing) {
        // The leg lies on the facet: across each edge it must point into the facet's side of that edge.
        if (facet_towards(e1, u1) != pair.shared_facet || facet_towards(e2, u2) != pair.shared_facet) continue;
        if (!grazing_angles(e1, u1, side, va, /*graze_is_source=*/false, wa1)) continue;
        if (!grazing_angles(e2, u2, side, vt2, /*graze_is_source=*/true, wa2)) continue;
      } else {
        if (!wedge_angles(e1, va, w1, wa1) || !wedge_angles(e2, w2, vt2, wa2)) continue;
      }
      // Edge 1's diffracted wave at Q2: radius s12 along φ̂1 (across edge 1), s' + s12 along β̂1; edge 2's
      // plane of incidence cuts it along t2 (⟂ ŝ12, in the plane of ŝ12 and edge 2).
      const double rho1 = s12, rho2 = s_in + s12;
      const Vec3 phi1 = d.cross(s_hat_mid).normalized();
      const Vec3 section = (e2.direction - e2.direction.dot(s_hat_mid) * s_hat_mid).normalized();
      const double cos2 = sq(section.dot(phi1));
      const double rho_e = 1.0 / (cos2 / rho1 + (1.0 - cos2) / rho2);
      const double l1 = s_in * s12 * sin_beta1 * sin_beta1 / (s_in + s12);
      const double l2 = s_out * (rho_e + s_out) * rho1 * rho2 * sin_beta2 * sin_beta2 /
                        (rho_e * (rho1 + s_out) * (rho2 + s_out));
      const auto coefficients = [&](const WedgeAngles& w, double beta0, double l) {
        const RadioMaterial& m0 = materials[facets[w.face0].material];
        const RadioMaterial& mn = materials[facets[w.facen].material];
        const FresnelCoefficients r0 = material_reflection(m0, f, std::abs(std::sin(w.phi_prime_rad)));
        const FresnelCoefficients rn = material_reflection(mn, f, std::abs(std::sin(w.n * kPi - w.phi_rad)));
        return wedge_diffraction(w.n, w.phi_rad, w.phi_prime_rad, beta0, l, k, r0, rn);
      };
      const UtdCoefficients d1 = coefficients(wa1, beta1, l1);
      UtdCoefficients d2 = coefficients(wa2, beta2, l2);
      if (grazing) d2.hard *= 0.5;  // KP: at grazing incidence the hard coefficient's two terms are one field
      // Edge-fixed bases (KP), as in diffraction.cpp: φ̂' = −ê × ŝ' / |·|, β̂0' = φ̂' × ŝ', φ̂ = ê × ŝ / |·|, β̂0 = φ̂ × ŝ.
      const Vec3 phi_in1 = -(d.cross(s_hat_in)).normalized(), beta_in1 = phi_in1.cross(s_hat_in);
      const Vec3 phi_out1 = d.cross(s_hat_mid).normalized(), beta_out1 = phi_out1.cross(s_hat_mid);
      const Vec3& d2v = e2.direction;
      const Vec3 phi_in2 = -(d2v.cross(s_hat_mid)).normalized(), beta_in2 = phi_in2.cross(s_hat_mid);
      const Vec3 phi_out2 = d2v.cross(s_hat_out).normalized(), beta_out2 = phi_out2.cross(s_hat_out);
      const CVec3 e_in = ant.polarization.field(ant.pose.orientation, s_hat_in);
      const CVec3 e_mid = -(d1.soft * beta_in1.cast<C>().dot(e_in)) * beta_out1.cast<C>() -
                          (d1.hard * phi_in1.cast<C>().dot(e_in)) * phi_out1.cast<C>();
      const CVec3 e_out = -(d2.soft * beta_in2.cast<C>().dot(e_mid)) * beta_out2.cast<C>() -
                          (d2.hard * phi_in2.cast<C>().dot(e_mid)) * phi_out2.cast<C>();
      const double gain = std::sqrt(ant.pattern.gain_linear_world(ant.pose.orientation, s_hat_in) *
                                    tag.pattern.gain_linear_world(tag.pose.orientation, -s_hat_out));
      const double spreading = (length / s_in) * std::sqrt(s_in / (s12 * (s_in + s12))) *
                               std::sqrt(rho_e / (s_out * (rho_e + s_out)));
      const C coefficient = gain * spreading *
                            polarization_match(e_out, tag.polarization, tag.pose.orientation, s_hat_out);
      const C contribution = path_contribution(length, coefficient, f);
      if (std::norm(contribution) < floor) continue;  // would be dropped: no ray for it
      // Legs: from each edge point (where float precision matters), stopping short of the ends; the grazing
      // leg just off its face on its side.
      const double end_in = std::min(options_.endpoint_epsilon_m, 0.25 * s_in);
      const double end_out = std::min(options_.endpoint_epsilon_m, 0.25 * s_out);
      const double end_mid = std::min(options_.endpoint_epsilon_m, 0.25 * s12);
      const Vec3 mid_origin = grazing ? Vec3(q1 + options_.surface_epsilon_m * side) : q1;
      if (bvh.occluded(q1, -s_hat_in, end_in, s_in - end_in) ||
          bvh.occluded(mid_origin, s_hat_mid, end_mid, s12 - end_mid) ||
          bvh.occluded(q2, s_hat_out, end_out, s_out - end_out))
        continue;
      TracedPath p;
      p.kind = PathKind::kDiffraction2;
      p.length_m = length;
      p.point = q1;
      p.point2 = q2;
      p.material = facets[wa1.face0].material;
      p.material2 = facets[wa2.face0].material;
      p.facet = wa1.face0;
      p.facet2 = wa2.face0;
      p.edge = i1;
      p.edge2 = i2;
      p.coefficient = coefficient;
      p.contribution = contribution;
      out.push_back(p);
    }
  }
}

}  // namespace rfidray
