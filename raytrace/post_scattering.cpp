// Levels full-selective and full: the field a thin metal post scatters (raytrace/thin_posts.h), one path per post,
// in place of the reflections off its faces and the diffraction at its edges (which the path finder leaves out for
// a post's facets and edges) and of its shadow on the direct path (which passes through it: the scattered field
// cancels the incident one behind the post, as it does in the exact solution).
//
// The post is a perfectly conducting circular cylinder of the post's equivalent radius a (its cross-section's
// logarithmic capacity). For an infinite cylinder the exact two-dimensional solution (core/cylinder_scattering.h)
// maps onto a point source by stationary phase along the axis, as UTD maps a wedge's: the path is the unfolded
// straight line from the antenna A to the tag T through the axis point Q that divides it in the ratio of their
// distances ρ', ρ from the axis; with L = |AQ| + |QT| = √((ρ' + ρ)² + Δz²), sin β = (ρ' + ρ)/L and k_t = k sin β
// (oblique incidence: the transverse problem at k_t, in which a perfect conductor keeps soft and hard apart),
//   h_post = √(G_A G_T) · λ/(4πL) e^{−jkL} · p_T · [ −R_s (e_A·β̂')β̂ − R_h (e_A·φ̂')φ̂ ] · T,
//   R = u_s(k_t a; k_t ρ', k_t ρ, φ − φ') / H0^(2)_far(k_t (ρ' + ρ)),
// in UTD's edge-fixed bases (raytrace/path_finder.h), u_s the scattered field of core/cylinder_scattering.h for
// each polarization, H0_far its far free-space field. Far from the post this is the cylinder's scattered ray with
// its 3-D spreading (that of a UTD edge ray); straight behind the post R → −1 and h_post cancels the direct path.
// The 2-D → 3-D mapping is exact only for ρ, ρ' ≫ λ, but it keeps the 2-D solution's near field: against FDTD, a
// 5 cm post 1.5 m from the source, tags 5–30 cm behind it: within 0.02–0.09 of free space (docs/fullwave.md).
//
// A finite post: T, the physical-optics truncation of the integral along the axis at the nearer end (the post as
// semi-infinite from there): T = ∫_{−∞}^{τ} e^{−jt²} dt / (√π e^{−jπ/4}), τ = √(k q) · (how far inside that end Q
// lies), q = ½ (ρ'²/|AQ|³ + ρ²/|QT|³) the path length's curvature along the axis. T → 1 deep inside, ½ at the end,
// → 0 beyond it, continuously as a tag moves over a post's top. The farther end is left out: its ripple (both ends
// truncated: 0.84–1.19) is not in the FDTD field, which it put 0.10–0.12 off, against 0.03–0.09 with one end.
//
// Both legs must be clear of everything but thin posts (several posts in line each scatter once: no multiple
// scattering between posts), however many posts stand on them: each leg is one ray that looks through every post's
// triangles (EmbreeScene::occluded_except). Other paths' legs still see a post as an obstacle.
#include <array>
#include <cmath>
#include <complex>

#include "core/cylinder_scattering.h"
#include "core/units.h"
#include "core/utd.h"
#include "raytrace/line_feet.h"
#include "raytrace/path_finder.h"

namespace rfidray {
namespace {

using C = std::complex<double>;

}  // namespace

void PathFinder::post_scatterings(const Endpoint& ant, const Endpoint& tag, double f, double floor,
                                  std::vector<TracedPath>& out) const {
  const auto& posts = posts_.posts;
  if (posts.empty()) return;
  const Vec3& a = ant.pose.position;
  const Vec3& t = tag.pose.position;
  const double k = wavenumber_rad_m(f);
  const C full_integral = std::sqrt(kPi) * std::polar(1.0, -0.25 * kPi);
  const EmbreeScene& bvh = scene_->bvh();
  // |h_post| ≤ √(G_A G_T) · λ/(4πL) · |T| · (B_s |e_β| |p_T(β̂)| + B_h |e_φ| |p_T(φ̂)|), p_T the tag's polarization
  // match (linear in the field it receives) and B_s, B_h the cylinder's bounds of |R_s|, |R_h| for every k_t ≤ k
  // (core/cylinder_scattering.h): a post below the floor by it is skipped before its coefficients and series, as it
  // would be after them. One bound per post radius and frequency, a few per scene, kept per thread across links (a
  // pure function of k and the radius: which thread computed it changes nothing).
  const double lambda = wavelength_m(f);
  struct CachedBound {
    double k = 0.0, radius_m = 0.0;  // the radius rounded up
    CylinderScatteringBound bound;
  };
  thread_local std::array<CachedBound, 16> tl_bounds{};
  thread_local size_t tl_bound_count = 0, tl_bound_next = 0;
  const auto bound_for = [&](double radius_m) -> const CylinderScatteringBound* {
    // Rounded up to 0.1 mm: a bound holds for every thinner cylinder, and posts of one size have radii that differ
    // in the last digits (each its own cross-section's capacity).
    double key = std::ceil(radius_m * 1e4) * 1e-4;
    if (key < radius_m) key += 1e-4;  // the product rounded below the radius
    for (size_t i = 0; i < tl_bound_count; ++i)
      if (tl_bounds[i].k == k && tl_bounds[i].radius_m == key) return &tl_bounds[i].bound;
    const double ka_max = k * key;
    if (!(ka_max > 0.0 && ka_max <= kCylinderMaxKa)) return nullptr;
    CachedBound& slot = tl_bounds[tl_bound_next];  // the oldest once full
    slot = {k, key, CylinderScatteringBound(ka_max)};
    tl_bound_next = (tl_bound_next + 1) % tl_bounds.size();
    if (tl_bound_count < tl_bounds.size()) ++tl_bound_count;
    return &slot.bound;
  };
  for (uint32_t pi = 0; pi < posts.size(); ++pi) {
    const ThinPost& post = posts[pi];
    const Vec3& d = post.direction;
    const LineFeet feet = line_feet(post.base, d, a, t);
    const double za = feet.z_a, zt = feet.z_t;
    const Vec3& va = feet.v_a;
    const Vec3& vt = feet.v_t;
    const double rho_a = feet.rho_a, rho_t = feet.rho_t;
    if (rho_a < 1e-6 || rho_t < 1e-6) continue;  // an end on the axis: inside the post
    const double lt = rho_a + rho_t, dz = zt - za;
    const double length = std::hypot(lt, dz);
    if (length * length > max_length2_) continue;
    const double zs = za + dz * rho_a / lt;
    const double r1 = std::hypot(rho_a, zs - za), r2 = std::hypot(rho_t, zt - zs);
    const double q = 0.5 * (rho_a * rho_a / (r1 * r1 * r1) + rho_t * rho_t / (r2 * r2 * r2));
    const double tau = std::sqrt(k * q) * std::min(zs, post.length_m - zs);
    const C truncation = fresnel_from_minus_infinity(tau) / full_integral;
    const double k_t = k * lt / length;
    const double ka = k_t * post.radius_m;
    if (!(ka > 0.0) || ka > kCylinderMaxKa) continue;  // not thin at this frequency (≥ 40 GHz for a 0.15 m post)
    const double xs = k_t * rho_a, xo = k_t * rho_t;
    const Vec3 qp = post.base + zs * d;
    const Vec3 s_hat_in = (qp - a) / r1, s_hat_out = (t - qp) / r2;
    // Edge-fixed bases (KP), as for a diffracted ray: φ̂' = −ê × ŝ' / |·|, β̂0' = φ̂' × ŝ', φ̂ = ê × ŝ / |·|, β̂0 = φ̂ × ŝ.
    const Vec3 phi_in = -(d.cross(s_hat_in)).normalized();
    const Vec3 beta_in = phi_in.cross(s_hat_in);
    const Vec3 phi_out = d.cross(s_hat_out).normalized();
    const Vec3 beta_out = phi_out.cross(s_hat_out);
    const CVec3 e_in = ant.polarization.field(ant.pose.orientation, s_hat_in);
    const C e_beta = beta_in.cast<C>().dot(e_in);
    const C e_phi = phi_in.cast<C>().dot(e_in);
    const double gain = std::sqrt(ant.pattern.gain_linear_world(ant.pose.orientation, s_hat_in) *
                                  tag.pattern.gain_linear_world(tag.pose.orientation, -s_hat_out));
    if (const CylinderScatteringBound* bound = bound_for(post.radius_m)) {
      // The tag's match is linear in the field: |p_T(e_out)| ≤ |R_s||e_β||p_T(β̂)| + |R_h||e_φ||p_T(φ̂)|.
      const CylinderBoundRatios most_r = bound->ratio(xs, xo);  // +∞ (an end too close for the bound) never skips
      const auto match = [&](const Vec3& v) {
        return std::abs(polarization_match(v.cast<C>(), tag.polarization, tag.pose.orientation, s_hat_out));
      };
      const double most = gain * std::abs(truncation) * lambda / (4.0 * kPi * length) *
                          (most_r.soft * std::abs(e_beta) * match(beta_out) +
                           most_r.hard * std::abs(e_phi) * match(phi_out));
      if (most * most < floor) continue;
    }
    const double delta_phi = std::atan2(d.dot(va.cross(vt)), va.dot(vt));
    const CylinderCoefficients c = cylinder_coefficients(ka, cylinder_terms(ka, xs, xo));
    const C far = hankel2_zero_far(k_t * lt);
    const CylinderField u = cylinder_scattered(c, xs, xo, delta_phi);
    const C r_soft = u.soft / far * truncation, r_hard = u.hard / far * truncation;
    const CVec3 e_out = -(r_soft * e_beta) * beta_out.cast<C>() - (r_hard * e_phi) * phi_out.cast<C>();
    const C coefficient = gain * polarization_match(e_out, tag.polarization, tag.pose.orientation, s_hat_out);
    const C contribution = path_contribution(length, coefficient, f);
    if (std::norm(contribution) < floor) continue;  // would be dropped: no ray for it
    // The legs up to the post's circumscribed cylinder (radius width/2): inside it there is only the post. The
    // transverse distance falls linearly along a leg to 0 at Q, so a leg meets that cylinder R/ρ of its length
    // before Q.
    const double radius_out = 0.5 * post.width_m;
    const double end_in = std::min(options_.endpoint_epsilon_m, 0.25 * r1);
    const double end_out = std::min(options_.endpoint_epsilon_m, 0.25 * r2);
    const double leg_in_far = r1 * (1.0 - radius_out / rho_a), leg_out_near = r2 * radius_out / rho_t;
    // One ray per leg: Embree looks through every post's triangles (occluded_except), however many posts it crosses.
    if (bvh.occluded_except(a, s_hat_in, end_in, leg_in_far, skip_post_triangle, this) ||
        bvh.occluded_except(qp, s_hat_out, leg_out_near, r2 - end_out, skip_post_triangle, this))
      continue;
    TracedPath p;
    p.kind = PathKind::kPostScattering;
    p.length_m = length;
    p.point = qp;
    p.material = post.material;
    p.post = pi;
    p.coefficient = coefficient;
    p.contribution = contribution;
    out.push_back(p);
  }
}

}  // namespace rfidray
