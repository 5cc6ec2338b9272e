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
    const double curvature = feet_.rho_a * feet_.rho_a / (s_in_ * s_in_ * s_in_) +
                             feet_.rho_t * feet_.rho_t / (s_out_ * s_out_ * s_out_);
    dz_dtau_q_ = std::sqrt(2.0 / (k * curvature));
  }
  double zq() const { return zq_; }
  double dz_dtau_q() const { return dz_dtau_q_; }
  double tau(double z) const { return std::copysign(std::sqrt(std::max(0.0, k_ * detour(z))), z - zq_); }
  double g(double z, double t, double weight) const {
    return weight * amplitude(z) / amplitude(zq_) * (2.0 * t / (k_ * slope(z))) / dz_dtau_q_;
  }

 private:
  double dist_a(double z) const { return Distance(feet_.rho_a, z - feet_.z_a); }
  double dist_t(double z) const { return Distance(feet_.rho_t, z - feet_.z_t); }
  // L(z) − L(z_Q) = Σ (d(z)² − d(z_Q)²)/(d(z) + d(z_Q)) = (z − z_Q)·Σ (z + z_Q − 2 z_end)/(d(z) + d(z_Q)).
  double detour(double z) const {
    return (z - zq_) * ((z + zq_ - 2.0 * feet_.z_a) / (dist_a(z) + s_in_) +
                        (z + zq_ - 2.0 * feet_.z_t) / (dist_t(z) + s_out_));
  }
  double amplitude(double z) const { return 1.0 / (dist_a(z) * dist_t(z)); }
  double slope(double z) const { return (z - feet_.z_a) / dist_a(z) + (z - feet_.z_t) / dist_t(z); }  // L'(z)

  LineFeet feet_;
  double k_, zq_, s_in_, s_out_, dz_dtau_q_;
};

// The edge integral of edge_truncation for one edge and link: its value for a pattern weight, or a bound on its
// deficit from the ends' weights alone (the bound's geometry is taken at construction, the value's when asked).
class EdgeIntegral {
 public:
  // `feet`: line_feet of the edge's line and the two ends.
  EdgeIntegral(const LineFeet& feet, double length_m, double k) : feet_(feet), length_m_(length_m), k_(k) {
    const IntegralGeometry<sqrt_distance> geometry(feet, k);
    t0_ = geometry.tau(0.0);
    t1_ = geometry.tau(length_m);
    // The bound's τ must put both ends where the value does not move them (|τ| ≥ kTauNear), with a margin.
    bounded_ = std::abs(t0_) >= kTauNear * (1.0 + 1e-6) && std::abs(t1_) >= kTauNear * (1.0 + 1e-6);
    if (bounded_) {
      g_per_weight_at_start_ = geometry.g(0.0, t0_, 1.0);
      g_per_weight_at_end_ = geometry.g(length_m, t1_, 1.0);
    }
  }

  // T of edge_truncation; `end_weight` as there.
  std::complex<double> share(const std::function<double(double)>& end_weight) const {
    const IntegralGeometry<hypot_distance> geometry(feet_, k_);
    const double t0 = geometry.tau(0.0), t1 = geometry.tau(length_m_);
    const auto end_term = [&](double z, double t) -> std::complex<double> {
      if (std::abs(t) < kTauNear) {
        const double side = z < geometry.zq() ? -1.0 : 1.0;
        z = geometry.zq() + side * kTauNear * geometry.dz_dtau_q();
        t = geometry.tau(z);
        if (!(std::abs(t) > 0.0)) return 0.0;
      }
      const double weight = end_weight ? end_weight(z) : 1.0;
      return (geometry.g(z, t, weight) - 1.0) * std::polar(1.0, -t * t) / std::complex<double>(0.0, -2.0 * t);
    };
    const std::complex<double> whole = std::sqrt(kPi) * std::polar(1.0, -kPi / 4.0);
    return (fresnel_from_minus_infinity(t1) - fresnel_from_minus_infinity(t0) + end_term(length_m_, t1) -
            end_term(0.0, t0)) /
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

std::optional<EdgeEnd> find_edge_end(const PathFinder& finder, const Endpoint& antenna, const Endpoint& tag,
                                     double f) {
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
  std::optional<EdgeEnd> worst;
  for (uint32_t ei = 0; ei < edges.size(); ++ei) {
    if (!post_of_edge.empty() && post_of_edge[ei] != kNoPost) continue;  // modelled as a cylinder, not as edges
    const Edge& e = edges[ei];
    const LineFeet feet = line_feet(e.start, e.direction, a, t);
    if (feet.rho_a < kOnEdge || feet.rho_t < kOnEdge) continue;
    const double zq = fermat_point_z(feet);
    const double past_end = std::max(-zq, zq - e.length_m);  // < 0: on the edge
    // s', s and sin β₀ of the (possibly extended) edge's Keller point.
    const Vec3 q = e.start + zq * e.direction;
    const Vec3 sa = q - a, st = t - q;
    const double s_in = sa.norm(), s_out = st.norm();
    if (!(s_in > 0.0) || !(s_out > 0.0)) continue;
    const double sin_beta = (sa / s_in).cross(e.direction).norm();
    if (sin_beta < 1e-9) continue;
    const double half_width = std::sqrt(lambda * s_in * s_out / (s_in + s_out)) / sin_beta;
    if (std::abs(past_end) > kHalfWidthsChecked * half_width) continue;  // deep inside or far past: |step − T| small
    WedgeAngles w;
    if (!wedge_angles(e, feet.v_a, feet.v_t, w)) continue;
    const double length = s_in + s_out;
    const double l_utd = s_in * s_out * sin_beta * sin_beta / length;
    const double q_pattern = pattern(q);
    if (!(q_pattern > 0.0)) continue;
    const double step = past_end <= 0.0 ? 1.0 : 0.0;
    // Before the UTD coefficients: each of D's four terms is at most 1/(2√(πX)) of the diffracted ray's free-space
    // field (|F(X)| < 1, |R| ≤ 1; core/utd.h, tests/core/test_utd.cpp), so the share is at most
    // (r / (s + s'))·2/√(π X_min) with the patterns' ratio. An edge whose estimate cannot reach what is reported, or
    // the worst so far, is skipped: the result is the same as with its coefficients computed.
    const double x_min = utd_min_transition_argument(w.n, w.phi_rad, w.phi_prime_rad, k * l_utd);
    const double pattern_ratio = q_pattern / direct_pattern;
    const double share_bound = r / length * 2.0 * 1.001 / std::sqrt(kPi * x_min) * pattern_ratio;
    const auto below_reported = [&](double bound) {
      return bound < kEdgeEndReported || (worst && bound <= worst->estimated_error);
    };
    // So is an edge whose estimate cannot reach it with |step − T| bounded (EdgeIntegral::deficit_bound): first at
    // the ends' largest pattern weight (no pattern evaluated along the edge; on a w1m map 63 % of the edges near an
    // end stop here), then at the ends' own weights (all the end terms read; 22 % more), before the integral itself.
    const EdgeIntegral integral(feet, e.length_m, k);
    const auto bound_below_reported = [&](double deficit_bound) {
      return x_min > 0.0 && below_reported(share_bound * (deficit_bound * (1.0 + 1e-6) + 1e-12));
    };
    const double max_weight = max_pattern / q_pattern;
    if (bound_below_reported(integral.deficit_bound(step, max_weight, max_weight))) continue;
    const Vec3 end = e.start + e.length_m * e.direction;
    const double weight_at_start = pattern(e.start) / q_pattern, weight_at_end = pattern(end) / q_pattern;
    if (bound_below_reported(integral.deficit_bound(step, weight_at_start, weight_at_end))) continue;
    const auto weight = [&](double z) {  // the ends' weights are the two just evaluated
      if (z == 0.0) return weight_at_start;
      if (z == e.length_m) return weight_at_end;
      return pattern(e.start + z * e.direction) / q_pattern;
    };
    const double deficit = std::abs(step - integral.share(weight));
    if (x_min > 0.0 && below_reported(share_bound * deficit)) continue;
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
    if (!std::isfinite(estimate) || estimate < kEdgeEndReported || (worst && estimate <= worst->estimated_error))
      continue;
    // The point's legs (its nearer end's when it is past the edge) must be clear for the term to be there at all.
    const Vec3 p = e.start + std::clamp(zq, 0.0, e.length_m) * e.direction;
    const Vec3 pa = p - a, pt = t - p;
    const double p_in = pa.norm(), p_out = pt.norm();
    if (!(p_in > 0.0) || !(p_out > 0.0)) continue;
    if (!legs_clear(finder.scene().bvh(), p, pa / p_in, p_in, pt / p_out, p_out, finder.options().endpoint_epsilon_m))
      continue;
    worst = EdgeEnd{past_end, half_width, share, estimate};
  }
  return worst;
}

}  // namespace rfidray
