// The edge-end check (raytrace/edge_end_finder.h has the formulas).
#include "raytrace/edge_end_finder.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/fresnel.h"
#include "core/units.h"
#include "core/utd.h"
#include "raytrace/diffraction_legs.h"
#include "raytrace/line_feet.h"
#include "raytrace/path_finder.h"

namespace rfidray {
namespace {

constexpr double kOnEdge = 1e-6;          // metres: an end this close to the edge's line sees no wedge angle
constexpr double kHalfWidthsChecked = 4;  // |step − T| about 0.04 or less beyond (edge_end_finder.h)

}  // namespace

namespace {

// The distance from an end to the edge point z in cylindrical coordinates about the edge's line, √(ρ² + Δz²):
// std::hypot for the integral's value (as it always was), a plain square root for its bound (a few ulps apart,
// well inside the bound's margin, and several times faster).
double hypot_distance(double rho, double dz) { return std::hypot(rho, dz); }
double sqrt_distance(double rho, double dz) { return std::sqrt(rho * rho + dz * dz); }

// Each end's correction: (g − 1)·e^{−jτ²}/(−2jτ), g = f(z)/f(Q) · (dz/dτ)(z)/(dz/dτ)(Q), dz/dτ = 2τ/(k L'(z)). It
// is smooth through τ = 0 (g − 1 = O(τ)), but g − 1 is formed from two small numbers there: within |τ| < kTauNear
// of the Keller point it is taken at |τ| = kTauNear on the end's side (an error of about kTauNear·|h'|).
constexpr double kTauNear = 1e-3;

// The geometry of the edge integral about the edge's line: the Keller point z_Q, τ(z) and g(z).
template <double (*Distance)(double, double)>
class IntegralGeometry {
 public:
  IntegralGeometry(const LineFeet& feet, double k) : feet_(feet), k_(k) {
    // The distances are exactly the 3-D ones, but the detour L(z) − L(z_Q) below is formed without subtracting two
    // path lengths of metres (which leaves ~1e-15 m of it: τ and the end term were noise for an end within ~10 µm
    // of the Keller point, |T| up to 42 where it is 0.44).
    zq_ = fermat_point_z(feet_);
    s_in_ = dist_a(zq_);
    s_out_ = dist_t(zq_);
    amplitude_q_ = amplitude(Point{zq_, s_in_, s_out_});
    const double curvature = feet_.rho_a * feet_.rho_a / (s_in_ * s_in_ * s_in_) +
                             feet_.rho_t * feet_.rho_t / (s_out_ * s_out_ * s_out_);
    dz_dtau_q_ = std::sqrt(2.0 / (k * curvature));
  }
  double zq() const { return zq_; }
  double dz_dtau_q() const { return dz_dtau_q_; }
  // An edge point z with its distances to the two ends (each square root taken once for τ and g there).
  struct Point {
    double z, dist_a, dist_t;
  };
  Point point(double z) const { return {z, dist_a(z), dist_t(z)}; }
  double tau(const Point& p) const { return std::copysign(std::sqrt(std::max(0.0, k_ * detour(p))), p.z - zq_); }
  double g(const Point& p, double t, double weight) const {
    return weight * amplitude(p) / amplitude_q_ * (2.0 * t / (k_ * slope(p))) / dz_dtau_q_;
  }

 private:
  double dist_a(double z) const { return Distance(feet_.rho_a, z - feet_.z_a); }
  double dist_t(double z) const { return Distance(feet_.rho_t, z - feet_.z_t); }
  // L(z) − L(z_Q) = Σ (d(z)² − d(z_Q)²)/(d(z) + d(z_Q)) = (z − z_Q)·Σ (z + z_Q − 2 z_end)/(d(z) + d(z_Q)).
  double detour(const Point& p) const {
    return (p.z - zq_) * ((p.z + zq_ - 2.0 * feet_.z_a) / (p.dist_a + s_in_) +
                          (p.z + zq_ - 2.0 * feet_.z_t) / (p.dist_t + s_out_));
  }
  static double amplitude(const Point& p) { return 1.0 / (p.dist_a * p.dist_t); }
  double slope(const Point& p) const {  // L'(z)
    return (p.z - feet_.z_a) / p.dist_a + (p.z - feet_.z_t) / p.dist_t;
  }

  LineFeet feet_;
  double k_, zq_, s_in_, s_out_, amplitude_q_, dz_dtau_q_;
};

// The edge integral of edge_truncation for one edge and link: its value for a pattern weight, or a bound on its
// deficit from the ends' weights alone (the bound's geometry is taken at construction, the value's when asked).
class EdgeIntegral {
 public:
  // `feet`: line_feet of the edge's line and the two ends.
  EdgeIntegral(const LineFeet& feet, double length_m, double k) : feet_(feet), length_m_(length_m), k_(k) {
    const IntegralGeometry<sqrt_distance> geometry(feet, k);
    const auto start = geometry.point(0.0), end = geometry.point(length_m);
    t0_ = geometry.tau(start);
    t1_ = geometry.tau(end);
    // The bound's τ must put both ends where the value does not move them (|τ| ≥ kTauNear), with a margin.
    bounded_ = std::abs(t0_) >= kTauNear * (1.0 + 1e-6) && std::abs(t1_) >= kTauNear * (1.0 + 1e-6);
    if (bounded_) {
      g_per_weight_at_start_ = geometry.g(start, t0_, 1.0);
      g_per_weight_at_end_ = geometry.g(end, t1_, 1.0);
    }
  }

  // T of edge_truncation; `end_weight` as there.
  std::complex<double> share(const std::function<double(double)>& end_weight) const {
    const IntegralGeometry<hypot_distance> geometry(feet_, k_);
    using Point = IntegralGeometry<hypot_distance>::Point;
    const Point start = geometry.point(0.0), end = geometry.point(length_m_);
    const double t0 = geometry.tau(start), t1 = geometry.tau(end);
    const auto end_term = [&](Point p, double t) -> std::complex<double> {
      if (std::abs(t) < kTauNear) {
        const double side = p.z < geometry.zq() ? -1.0 : 1.0;
        p = geometry.point(geometry.zq() + side * kTauNear * geometry.dz_dtau_q());
        t = geometry.tau(p);
        if (!(std::abs(t) > 0.0)) return 0.0;
      }
      const double weight = end_weight ? end_weight(p.z) : 1.0;
      return (geometry.g(p, t, weight) - 1.0) * std::polar(1.0, -t * t) / std::complex<double>(0.0, -2.0 * t);
    };
    const std::complex<double> whole = std::sqrt(kPi) * std::polar(1.0, -kPi / 4.0);
    return (fresnel_from_minus_infinity(t1) - fresnel_from_minus_infinity(t0) + end_term(end, t1) -
            end_term(start, t0)) /
           whole;
  }

  // An upper bound on |step − T| for every end_weight with these values at the ends (step: 1 with the Keller point
  // on the edge, 0 past it), +∞ when an end is within kTauNear of the Keller point (its end term is not bounded
  // here). With I(a) = ∫_a^∞ e^{−jτ²} dτ (a > 0), G(τ) = √π e^{−jπ/4} − I(τ) for τ > 0 and I(|τ|) for τ < 0,
  // so √π·|step − T| is at most Σ_ends |I(|τ|) ± h(τ)|, both forms of which are bounded here, the smaller taken:
  //   - |I(a)| ≤ min(√π/2 + a, 1/a) (|I(0)| = √π/2; by parts, I(a) = e^{−ja²}/(2ja) + R(a), |R| ≤ 1/(2a) + 1/(2a)),
  //     and |h| = |g − 1|/(2|τ|) with g ≥ 0 (τ and L' share their sign), so |g − 1| ≤ max(g, 1);
  //   - I's leading term cancels h's −1: I(a) ± h = g e^{−ja²}/(2ja) + R(a), and by parts once more
  //     |R(a)| ≤ 1/(2a³), so each end is at most g/(2|τ|) + 1/(2|τ|³).
  // g is proportional to the end's weight, so the bound grows with both.
  double deficit_bound(double step, double weight_at_start, double weight_at_end) const {
    constexpr double kInfinity = std::numeric_limits<double>::infinity();
    if (!bounded_) return kInfinity;
    if (step != this->step()) return kInfinity;  // rounding disagrees with the caller's side: no bound
    const auto end_bound = [](double t, double g) {
      const double a = std::abs(t);
      const double apart = std::min(0.5 * std::sqrt(kPi) + a, 1.0 / a) + std::max(g, 1.0) / (2.0 * a);
      const double joined = g / (2.0 * a) + 1.0 / (2.0 * a * a * a);
      return std::min(apart, joined) / std::sqrt(kPi);
    };
    return end_bound(t0_, weight_at_start * g_per_weight_at_start_) +
           end_bound(t1_, weight_at_end * g_per_weight_at_end_);
  }
  // The step the ends' τ give: 1 with the Keller point on the edge (τ₀ < 0 < τ₁), 0 past it.
  double step() const { return t0_ < 0.0 && t1_ > 0.0 ? 1.0 : 0.0; }

 private:
  LineFeet feet_;
  double length_m_, k_;
  double t0_, t1_;  // τ at the ends, for the bound
  bool bounded_ = false;
  double g_per_weight_at_start_ = 0.0, g_per_weight_at_end_ = 0.0;  // g at each end for weight 1 (when bounded)
};

}  // namespace

std::complex<double> edge_truncation(const Vec3& start, const Vec3& direction, double length_m, const Vec3& antenna,
                                     const Vec3& tag, double k, const std::function<double(double)>& end_weight) {
  return EdgeIntegral(line_feet(start, direction, antenna, tag), length_m, k).share(end_weight);
}

double edge_truncation_deficit_bound(const Vec3& start, const Vec3& direction, double length_m, const Vec3& antenna,
                                     const Vec3& tag, double k, double weight_at_start, double weight_at_end) {
  const EdgeIntegral integral(line_feet(start, direction, antenna, tag), length_m, k);
  return integral.deficit_bound(integral.step(), weight_at_start, weight_at_end);
}

namespace {

// kSkips: with the bounds, the square-root-free test and the edge tried first (find_edge_end); without them every
// edge near an end is evaluated in full, in index order (find_edge_end_without_skips).
// `checks` (without the skips only): what each edge near an end would be compared with (edge_end_checks).
template <bool kSkips>
std::optional<EdgeEnd> edge_end(const PathFinder& finder, const Endpoint& antenna, const Endpoint& tag, double f,
                                std::vector<EdgeEndCheck>* checks = nullptr) {
  const auto& edges = finder.edges();
  if (edges.empty()) return std::nullopt;
  const Vec3& a = antenna.pose.position;
  const Vec3& t = tag.pose.position;
  const auto post_of_edge = finder.post_of_edge();
  const auto& facets = finder.scene().facets();
  const auto& materials = finder.scene().materials();
  const double k = wavenumber_rad_m(f), lambda = wavelength_m(f);
  const double r = (t - a).norm();
  if (!a.allFinite() || !t.allFinite() || !(r > 0.0)) return std::nullopt;
  // √(G_R G_T) along the path via point p.
  const auto pattern = [&](const Vec3& p) {
    const Vec3 in = (p - a).normalized(), out = (t - p).normalized();
    return std::sqrt(antenna.pattern.gain_linear_world(antenna.pose.orientation, in) *
                     tag.pattern.gain_linear_world(tag.pose.orientation, -out));
  };
  const double direct_pattern = pattern(a + 0.5 * (t - a));
  if (!(direct_pattern > 0.0)) return std::nullopt;
  // pattern(p) ≤ this for every p (the bound of the edge integral's deficit below).
  const double max_pattern =
      std::sqrt(antenna.pattern.max_gain_linear() * tag.pattern.max_gain_linear()) * (1.0 + 1e-9);
  // The result is the lowest-indexed edge of largest estimate (among those with clear legs), whatever order the
  // edges are tried in. Tried first: the edge this thread reported last (a neighbouring cell's or pose's, most
  // often this link's too): its estimate, found early, lets the bounds below skip far more of the others than
  // kEdgeEndReported alone does.
  std::optional<EdgeEnd> worst;
  uint32_t worst_index = 0;
  // Whether an edge whose estimate is at most `bound` cannot become the result.
  const auto cannot_be_worst = [&](double bound, uint32_t ei) {
    return bound < kEdgeEndReported ||
           (worst && (bound < worst->estimated_error || (bound == worst->estimated_error && ei > worst_index)));
  };
  const auto try_edge = [&](uint32_t ei) {
    if (!post_of_edge.empty() && post_of_edge[ei] != kNoPost) return;  // modelled as a cylinder, not as edges
    const Edge& e = edges[ei];
    const LineFeet feet = line_feet(e.start, e.direction, a, t);
    if (feet.rho_a < kOnEdge || feet.rho_t < kOnEdge) return;
    const double zq = fermat_point_z(feet);
    const double past_end = std::max(-zq, zq - e.length_m);  // < 0: on the edge
    // Most edges are far from an end in half-widths: rejected here without a square root. With c = 1/sin β₀ =
    // √(1 + Δz²/(ρ_A + ρ_T)²), s' = c ρ_A and s = c ρ_T (Fermat), so the half-width below is exactly
    // √(λ c³ ρ_A ρ_T/(ρ_A + ρ_T)); the margin covers the rounding of both forms.
    const double rho_sum = feet.rho_a + feet.rho_t, dz_over_rho = (feet.z_t - feet.z_a) / rho_sum;
    const double c2 = 1.0 + dz_over_rho * dz_over_rho;
    const double half_width2_per_c = lambda * c2 * (feet.rho_a * feet.rho_t / rho_sum);
    const double past_end2 = past_end * past_end, checked2 = kHalfWidthsChecked * kHalfWidthsChecked;
    const bool far_from_the_ends =
        past_end2 * past_end2 > checked2 * checked2 * half_width2_per_c * half_width2_per_c * c2 * (1.0 + 1e-6);
    if (kSkips && far_from_the_ends) return;
    // s', s and sin β₀ of the (possibly extended) edge's Keller point.
    const Vec3 q = e.start + zq * e.direction;
    const Vec3 sa = q - a, st = t - q;
    const double s_in = sa.norm(), s_out = st.norm();
    if (!(s_in > 0.0) || !(s_out > 0.0)) return;
    const double sin_beta = (sa / s_in).cross(e.direction).norm();
    if (sin_beta < 1e-9) return;
    const double half_width = std::sqrt(lambda * s_in * s_out / (s_in + s_out)) / sin_beta;
    if (std::abs(past_end) > kHalfWidthsChecked * half_width) return;  // deep inside or far past: |step − T| small
    WedgeAngles w;
    if (!wedge_angles(e, feet.v_a, feet.v_t, w)) return;
    const double length = s_in + s_out;
    const double l_utd = s_in * s_out * sin_beta * sin_beta / length;
    const double step = past_end <= 0.0 ? 1.0 : 0.0;
    // Before the UTD coefficients: each of D's four terms is at most 1/(2√(πX)) of the diffracted ray's free-space
    // field (|F(X)| < 1, |R| ≤ 1; core/utd.h, tests/core/test_utd.cpp), so the share is at most
    // (r / (s + s'))·2/√(π X_min) with the patterns' ratio. An edge whose estimate cannot reach what is reported, or
    // the worst so far, is skipped: the result is the same as with its coefficients computed.
    const double x_min = utd_min_transition_argument(w.n, w.phi_rad, w.phi_prime_rad, k * l_utd);
    const double share_bound_per_ratio = r / length * 2.0 * 1.001 / std::sqrt(kPi * x_min);
    // So is an edge whose estimate cannot reach it with |step − T| bounded (EdgeIntegral::deficit_bound): first with
    // no pattern evaluated at all, then at the ends' largest pattern weight (no pattern along the edge), then at the
    // ends' own weights (all the end terms read), before the integral itself. The first: per end the bound is
    // min(A + max(g, 1)/(2a), g/(2a) + B) with g = (weight)·g₁, and the share carries the Keller point's pattern q;
    // with the weight M/q (M ≥ q the largest pattern) q times it is at most M times the bound at weight 1.
    const EdgeIntegral integral(feet, e.length_m, k);
    const auto estimate_bound = [&](double share_bound, double deficit_bound) {
      return x_min > 0.0 ? share_bound * (deficit_bound * (1.0 + 1e-6) + 1e-12)
                         : std::numeric_limits<double>::infinity();
    };
    const auto bound_below_reported = [&](double bound) { return kSkips && cannot_be_worst(bound, ei); };
    const double largest_pattern_ratio = max_pattern / direct_pattern;
    const double bound_without_patterns =
        estimate_bound(share_bound_per_ratio * largest_pattern_ratio, integral.deficit_bound(step, 1.0, 1.0));
    if (bound_below_reported(bound_without_patterns)) return;
    const double q_pattern = pattern(q);
    if (!(q_pattern > 0.0)) return;
    const double pattern_ratio = q_pattern / direct_pattern;
    const double share_bound = share_bound_per_ratio * pattern_ratio;
    const double max_weight = max_pattern / q_pattern;
    const double bound_at_largest_weight =
        estimate_bound(share_bound, integral.deficit_bound(step, max_weight, max_weight));
    if (bound_below_reported(bound_at_largest_weight)) return;
    const Vec3 end = e.start + e.length_m * e.direction;
    const double weight_at_start = pattern(e.start) / q_pattern, weight_at_end = pattern(end) / q_pattern;
    const double bound_at_end_weights =
        estimate_bound(share_bound, integral.deficit_bound(step, weight_at_start, weight_at_end));
    if (bound_below_reported(bound_at_end_weights)) return;
    const auto weight = [&](double z) {  // the ends' weights are the two just evaluated
      if (z == 0.0) return weight_at_start;
      if (z == e.length_m) return weight_at_end;
      return pattern(e.start + z * e.direction) / q_pattern;
    };
    const double deficit = std::abs(step - integral.share(weight));
    const double bound_with_integral = x_min > 0.0 ? share_bound * deficit : std::numeric_limits<double>::infinity();
    if (bound_below_reported(bound_with_integral)) return;
    const double beta0 = std::atan2(sin_beta, (sa / s_in).dot(e.direction));
    const RadioMaterial& m0 = materials[facets[w.face0].material];
    const RadioMaterial& mn = materials[facets[w.facen].material];
    const UtdCoefficients dc =
        wedge_diffraction(w.n, w.phi_rad, w.phi_prime_rad, beta0, l_utd, k,
                          material_reflection(m0, f, std::abs(std::sin(w.phi_prime_rad))),
                          material_reflection(mn, f, std::abs(std::sin(w.n * kPi - w.phi_rad))));
    const double share =
        r * std::max(std::abs(dc.soft), std::abs(dc.hard)) / std::sqrt(s_in * s_out * length) * pattern_ratio;
    const double estimate = share * deficit;
    if (checks)
      checks->push_back({ei, !far_from_the_ends, bound_without_patterns, bound_at_largest_weight, bound_at_end_weights,
                         bound_with_integral, estimate});
    if (!std::isfinite(estimate) || cannot_be_worst(estimate, ei)) return;
    // The point's legs (its nearer end's when it is past the edge) must be clear for the term to be there at all.
    const Vec3 p = e.start + std::clamp(zq, 0.0, e.length_m) * e.direction;
    const Vec3 pa = p - a, pt = t - p;
    const double p_in = pa.norm(), p_out = pt.norm();
    if (!(p_in > 0.0) || !(p_out > 0.0)) return;
    if (!legs_clear(finder.scene().bvh(), p, pa / p_in, p_in, pt / p_out, p_out, finder.options().endpoint_epsilon_m))
      return;
    worst = EdgeEnd{past_end, half_width, share, estimate};
    worst_index = ei;
  };
  constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  thread_local uint32_t tl_last_worst = kNone;
  const uint32_t first = kSkips && tl_last_worst < edges.size() ? tl_last_worst : kNone;
  if (first != kNone) try_edge(first);
  for (uint32_t ei = 0; ei < edges.size(); ++ei)
    if (ei != first) try_edge(ei);
  if (kSkips && worst) tl_last_worst = worst_index;
  return worst;
}

}  // namespace

std::optional<EdgeEnd> find_edge_end(const PathFinder& finder, const Endpoint& antenna, const Endpoint& tag,
                                     double frequency_hz) {
  return edge_end<true>(finder, antenna, tag, frequency_hz);
}

std::optional<EdgeEnd> find_edge_end_without_skips(const PathFinder& finder, const Endpoint& antenna,
                                                   const Endpoint& tag, double frequency_hz) {
  return edge_end<false>(finder, antenna, tag, frequency_hz);
}

std::vector<EdgeEndCheck> edge_end_checks(const PathFinder& finder, const Endpoint& antenna, const Endpoint& tag,
                                          double frequency_hz) {
  std::vector<EdgeEndCheck> checks;
  edge_end<false>(finder, antenna, tag, frequency_hz, &checks);
  return checks;
}

}  // namespace rfidray
