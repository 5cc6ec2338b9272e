// The edge-end check (raytrace/edge_end_finder.h has the formulas).
#include "raytrace/edge_end_finder.h"

#include <algorithm>
#include <cmath>

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

std::complex<double> edge_truncation(const Vec3& start, const Vec3& direction, double length_m, const Vec3& antenna,
                                     const Vec3& tag, double k, const std::function<double(double)>& end_weight) {
  // In cylindrical coordinates about the edge's line: the distance from an end to the edge point z is
  // √(ρ² + (z − z_end)²), exactly the 3-D distance, but the detour L(z) − L(z_Q) below is then formed without
  // subtracting two path lengths of metres (which leaves ~1e-15 m of it: τ and the end term were noise for an end
  // within ~10 µm of the Keller point, |T| up to 42 where it is 0.44).
  const LineFeet feet = line_feet(start, direction, antenna, tag);
  const double za = feet.z_a, zt = feet.z_t, rho_a = feet.rho_a, rho_t = feet.rho_t;
  const double zq = za + (zt - za) * rho_a / (rho_a + rho_t);
  const auto dist_a = [&](double z) { return std::hypot(rho_a, z - za); };
  const auto dist_t = [&](double z) { return std::hypot(rho_t, z - zt); };
  const double s_in = dist_a(zq), s_out = dist_t(zq);
  // L(z) − L(z_Q) = Σ (d(z)² − d(z_Q)²)/(d(z) + d(z_Q)) = (z − z_Q)·Σ (z + z_Q − 2 z_end)/(d(z) + d(z_Q)).
  const auto detour = [&](double z) {
    return (z - zq) * ((z + zq - 2.0 * za) / (dist_a(z) + s_in) + (z + zq - 2.0 * zt) / (dist_t(z) + s_out));
  };
  const auto amplitude = [&](double z) { return 1.0 / (dist_a(z) * dist_t(z)); };
  const auto slope = [&](double z) { return (z - za) / dist_a(z) + (z - zt) / dist_t(z); };  // L'(z)
  const double curvature = rho_a * rho_a / (s_in * s_in * s_in) + rho_t * rho_t / (s_out * s_out * s_out);
  const double dz_dtau_q = std::sqrt(2.0 / (k * curvature));
  const auto tau = [&](double z) { return std::copysign(std::sqrt(std::max(0.0, k * detour(z))), z - zq); };
  // Each end's correction: (g − 1)·e^{−jτ²}/(−2jτ), g = f(z)/f(Q) · (dz/dτ)(z)/(dz/dτ)(Q), dz/dτ = 2τ/(k L'(z)). It is
  // smooth through τ = 0 (g − 1 = O(τ)), but g − 1 is formed from two small numbers there: within |τ| < kTauNear
  // of the Keller point it is taken at |τ| = kTauNear on the end's side (an error of about kTauNear·|h'|).
  constexpr double kTauNear = 1e-3;
  const auto end_term = [&](double z, double t) -> std::complex<double> {
    if (std::abs(t) < kTauNear) {
      const double side = z < zq ? -1.0 : 1.0;
      z = zq + side * kTauNear * dz_dtau_q;
      t = tau(z);
      if (!(std::abs(t) > 0.0)) return 0.0;
    }
    const double weight = end_weight ? end_weight(z) : 1.0;
    const double g = weight * amplitude(z) / amplitude(zq) * (2.0 * t / (k * slope(z))) / dz_dtau_q;
    return (g - 1.0) * std::polar(1.0, -t * t) / std::complex<double>(0.0, -2.0 * t);
  };
  const double t1 = tau(length_m), t0 = tau(0.0);
  const std::complex<double> whole = std::sqrt(kPi) * std::polar(1.0, -kPi / 4.0);
  return (fresnel_from_minus_infinity(t1) - fresnel_from_minus_infinity(t0) + end_term(length_m, t1) -
          end_term(0.0, t0)) / whole;
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
  std::optional<EdgeEnd> worst;
  for (uint32_t ei = 0; ei < edges.size(); ++ei) {
    if (!post_of_edge.empty() && post_of_edge[ei] != kNoPost) continue;  // modelled as a cylinder, not as edges
    const Edge& e = edges[ei];
    const LineFeet feet = line_feet(e.start, e.direction, a, t);
    if (feet.rho_a < kOnEdge || feet.rho_t < kOnEdge) continue;
    const double zq = feet.z_a + (feet.z_t - feet.z_a) * feet.rho_a / (feet.rho_a + feet.rho_t);
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
    const auto weight = [&](double z) { return pattern(e.start + z * e.direction) / q_pattern; };
    const double deficit = std::abs(step - edge_truncation(e.start, e.direction, e.length_m, a, t, k, weight));
    // Before the UTD coefficients: each of D's four terms is at most 1/(2√(πX)) of the diffracted ray's free-space
    // field (|F(X)| < 1, |R| ≤ 1; core/utd.h, tests/core/test_utd.cpp), so the share is at most
    // (r / (s + s'))·2/√(π X_min) with the patterns' ratio. An edge whose estimate cannot reach what is reported, or
    // the worst so far, is skipped: the result is the same as with its coefficients computed.
    const double x_min = utd_min_transition_argument(w.n, w.phi_rad, w.phi_prime_rad, k * l_utd);
    const double pattern_ratio = q_pattern / direct_pattern;
    if (x_min > 0.0) {
      const double bound = r / length * 2.0 * 1.001 / std::sqrt(kPi * x_min) * pattern_ratio * deficit;
      if (bound < kEdgeEndReported || (worst && bound <= worst->estimated_error)) continue;
    }
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
