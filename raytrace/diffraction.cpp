// Level full: first-order UTD edge diffraction at every edge of raytrace/edges.h (raytrace/path_finder.h has
// the physics, core/utd.h the coefficients).
//
// Level full-selective: the same, only where diffraction matters. A link whose direct path is not clear (no
// `los` path: blocked, or through obstacles) takes every edge, as full does: there the diffracted field may be
// all there is. A link with a clear direct path skips an edge when the link lies more than N Fresnel-zone
// widths (TraceOptions::diffraction_fresnel_zones, default 3) from every incident and reflection shadow
// boundary of the edge, i.e. when the smallest transition-function argument X = kL·a of its four terms is
// ≥ π·N² (core/utd.h, utd_min_transition_argument). Justification (KP's transition function): near a boundary
// the diffracted field is what makes the total continuous (half the jumping GO field at X = 0); outside the
// transition region F(X) → 1 and each term is at most 1/(2√(πX)) of the free-space field over the diffracted
// ray's length, which is weaker than the direct path's (the diffracted ray is the longer), so a skipped edge
// adds at most 2/√(πX) ≈ 0.21 (X = 9π, all four terms at their bound; typically one or two terms, far less) of
// the direct field, for equal antenna gains along both. The test is a few multiplications and cosines per
// edge before any transition function is evaluated or any ray shot. The rule errs towards full: should the
// direct path ever not come first in `out`, every link is taken as shadowed.
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/edge_near_field.h"
#include "core/fresnel.h"
#include "core/units.h"
#include "core/utd.h"
#include "raytrace/path_finder.h"

namespace rfidray {
namespace {

// The received voltage of a near field `e` (not a ray: it may have a part along the arrival direction) at an
// antenna: a linear antenna takes the field along its axis (a short dipole's open-circuit voltage is l·E); others
// as a ray arriving along `arrival` (core/polarization.h).
std::complex<double> receive_near_field(const CVec3& e, const Endpoint& rx, const Vec3& arrival) {
  if (rx.polarization.kind == PolarizationKind::kLinear)
    return (rx.pose.orientation * rx.polarization.axis_local).cast<std::complex<double>>().dot(e);
  return polarization_match(e, rx.polarization, rx.pose.orientation, arrival);
}

// Level full: the edge's near field at whichever end is close to the edge (core/edge_near_field.h), a path of its
// own (kind edge-near-field) with the diffracted ray's legs and length, its coefficient relative to that length. The canonical problem is
// placed at the near end N, lit by the far end F as a plane wave of F's polarization and amplitude at the edge:
//   h_N = w · √(G_F G_N) · λ/(4π s_F) e^{−jk s_F} · p_N · [ (E_F·ê) ΔE_z ê − (E_F·φ̂') (ΔE_ρ ρ̂_N + ΔE_φ φ̂_N) ],
// with H^i_z = −(E_F·φ̂')/η for the hard part (φ̂' = −ê × ŝ / |ê × ŝ|, the tracer's basis), ρ̂_N, φ̂_N the near
// end's cylindrical unit vectors about ê (the canonical problem's ẑ).
std::complex<double> near_field_coefficient(const Edge& e, double n, double phi, double phi_prime, double sin_beta,
                                            const Vec3& va, const Vec3& vt, const Endpoint& ant, const Endpoint& tag,
                                            const Vec3& s_hat_in, double s_in, double length, double k) {
  const double rho_a = va.norm(), rho_t = vt.norm();
  const bool tag_near = rho_t <= rho_a;
  const double rho_near = tag_near ? rho_t : rho_a, rho_far = tag_near ? rho_a : rho_t;
  const double k_t = k * sin_beta;  // the transverse problem of oblique incidence
  const double w = edge_near_field_weight(k_t * rho_near, rho_far / rho_near, sin_beta);
  if (w <= 0.0) return 0.0;
  const Endpoint& near = tag_near ? tag : ant;
  const Endpoint& far = tag_near ? ant : tag;
  // The far end's ray to the edge point: for the antenna the incoming leg; for the tag the outgoing leg reversed.
  const Vec3 q = ant.pose.position + s_in * s_hat_in;
  const Vec3 s_far = (q - far.pose.position).normalized();
  const double s_far_m = (q - far.pose.position).norm();
  const EdgeNearField c = edge_near_field(n, rho_near, tag_near ? phi : phi_prime, tag_near ? phi_prime : phi, k_t);
  const Vec3& z = e.direction;
  const Vec3 rho_hat = (tag_near ? vt : va) / rho_near, phi_hat = z.cross(rho_hat);
  const Vec3 phi_in = -(z.cross(s_far)).normalized();
  const CVec3 e_far = far.polarization.field(far.pose.orientation, s_far);
  const std::complex<double> e_z = z.cast<std::complex<double>>().dot(e_far);
  const std::complex<double> e_phi = phi_in.cast<std::complex<double>>().dot(e_far);
  const CVec3 delta = (e_z * c.soft) * z.cast<std::complex<double>>() -
                      e_phi * (c.hard_e_rho * rho_hat.cast<std::complex<double>>() +
                               c.hard_e_phi * phi_hat.cast<std::complex<double>>());
  const double gain = std::sqrt(far.pattern.gain_linear_world(far.pose.orientation, s_far) *
                                near.pattern.gain_linear_world(near.pose.orientation, -s_far));
  // Relative to the diffracted path: λ/(4π s_F) e^{−jk s_F} over λ/(4π L) e^{−jkL}.
  return w * gain * (length / s_far_m) * std::polar(1.0, k * (length - s_far_m)) * receive_near_field(delta, near, s_far);
}

}  // namespace

void PathFinder::diffractions(const Endpoint& ant, const Endpoint& tag, double f, double floor,
                              std::vector<TracedPath>& out) const {
  const Vec3& a = ant.pose.position;
  const Vec3& t = tag.pose.position;
  const double k = wavenumber_rad_m(f);
  const auto& facets = scene_->facets();
  const auto& materials = scene_->materials();
  const EmbreeScene& bvh = scene_->bvh();
  constexpr double kOnEdge = 1e-6;  // metres: an end this close to the edge's line is on it (no wedge angle)
  // full-selective: a link with a clear direct path (the direct path, when present, comes first in `out`)
  // diffracts only near boundaries; NaN or ∞ zones skip nothing.
  const bool selective = !includes(options_.level, ChannelLevel::kFull) && !out.empty() &&
                         out.front().kind == PathKind::kLineOfSight;
  const double min_x = kPi * options_.diffraction_fresnel_zones * options_.diffraction_fresnel_zones;
  // What geometrical optics the tracer found (core/utd.h, GeometricOpticsSides): the direct path, and the
  // single reflections by facet. Near a boundary the diffracted field takes the side these say.
  const size_t found = out.size();  // the paths before diffraction (a few tens: scanned, not indexed)
  bool direct_found = false;
  for (size_t i = 0; i < found; ++i) direct_found |= out[i].kind == PathKind::kLineOfSight;
  const auto reflected = [&](uint32_t facet) {
    for (size_t i = 0; i < found; ++i)
      if (out[i].kind == PathKind::kReflection && out[i].facet == facet) return 1;
    return -1;
  };
  // Where float and double may disagree about a boundary: the tracer's rays are float (Embree), good to a few
  // ulps of the coordinates' size, and keep surface_epsilon_m off faces; as an angle at the nearer end's
  // distance from the edge (the band is ~5e-5 rad for 1 m coordinates 4 cm from an edge).
  const double scale_m = std::max({1.0, a.cwiseAbs().maxCoeff(), t.cwiseAbs().maxCoeff()});
  const double uncertain_m = std::max(32.0 * std::numeric_limits<float>::epsilon() * scale_m,
                                      4.0 * options_.surface_epsilon_m);
  for (uint32_t ei = 0; ei < edges_.size(); ++ei) {
    const Edge& e = edges_[ei];
    const Vec3& d = e.direction;
    // Feet of A and T on the edge's line and their distances from it.
    const Vec3 ra = a - e.start, rt = t - e.start;
    const double za = ra.dot(d), zt = rt.dot(d);
    const Vec3 va = ra - za * d, vt = rt - zt * d;
    const double rho_a = va.norm(), rho_t = vt.norm();
    if (rho_a < kOnEdge || rho_t < kOnEdge) continue;
    // Fermat: the unfolded path is straight, so Q divides [za, zt] in the ratio rho_a : rho_t.
    const double zq = za + (zt - za) * rho_a / (rho_a + rho_t);
    if (zq < 0.0 || zq > e.length_m) continue;
    const Vec3 q = e.start + zq * d;
    // Which exterior region holds both ends: measured from face a over angle α, or from face b over 2π − α.
    WedgeAngles w;
    if (!wedge_angles(e, va, vt, w)) continue;
    const double n = w.n, phi_prime = w.phi_prime_rad, phi = w.phi_rad;
    const uint32_t face0 = w.face0, facen = w.facen;
    const Vec3 sa = q - a, st = t - q;
    const double s_in = sa.norm(), s_out = st.norm();
    if (!(s_in > 0.0) || !(s_out > 0.0)) continue;
    const double length = s_in + s_out;
    if (length * length > max_length2_) continue;
    const Vec3 s_hat_in = sa / s_in, s_hat_out = st / s_out;
    const double sin_beta = s_hat_in.cross(d).norm();
    if (sin_beta < 1e-9) continue;
    const double beta0 = std::atan2(sin_beta, s_hat_in.dot(d));
    const double l_utd = s_in * s_out * sin_beta * sin_beta / length;
    if (selective && utd_min_transition_argument(n, phi, phi_prime, k * l_utd) >= min_x) continue;
    // Face reflection coefficients for Luebbers' form (perfect conductors: {−1, +1}, KP exactly).
    const RadioMaterial& m0 = materials[facets[face0].material];
    const RadioMaterial& mn = materials[facets[facen].material];
    const FresnelCoefficients r0 = material_reflection(m0, f, std::abs(std::sin(phi_prime)));
    const FresnelCoefficients rn = material_reflection(mn, f, std::abs(std::sin(n * kPi - phi)));
    GeometricOpticsSides sides;
    sides.band_rad = uncertain_m / std::min(rho_a, rho_t);
    // Within the band of a boundary (X = kL·a with a ≈ δ²/2 there; twice the margin) the tracer's sides decide.
    const double kl = k * l_utd;
    if (utd_min_transition_argument(n, phi, phi_prime, kl) < kl * sides.band_rad * sides.band_rad) {
      sides.incident = direct_found ? 1 : -1;
      sides.reflected_face0 = reflected(face0);
      sides.reflected_facen = reflected(facen);
    }
    const UtdCoefficients dc = wedge_diffraction(n, phi, phi_prime, beta0, l_utd, k, r0, rn, sides);
    // Edge-fixed polarization bases (KP): φ̂' = −ê × ŝ' / |·|, β̂0' = φ̂' × ŝ', φ̂ = ê × ŝ / |·|, β̂0 = φ̂ × ŝ.
    const Vec3 phi_in = -(d.cross(s_hat_in)).normalized();
    const Vec3 beta_in = phi_in.cross(s_hat_in);
    const Vec3 phi_out = d.cross(s_hat_out).normalized();
    const Vec3 beta_out = phi_out.cross(s_hat_out);
    const CVec3 e_in = ant.polarization.field(ant.pose.orientation, s_hat_in);
    const std::complex<double> e_beta = beta_in.cast<std::complex<double>>().dot(e_in);
    const std::complex<double> e_phi = phi_in.cast<std::complex<double>>().dot(e_in);
    const CVec3 e_out = -(dc.soft * e_beta) * beta_out.cast<std::complex<double>>() -
                        (dc.hard * e_phi) * phi_out.cast<std::complex<double>>();
    const double gain = std::sqrt(ant.pattern.gain_linear_world(ant.pose.orientation, s_hat_in) *
                                  tag.pattern.gain_linear_world(tag.pose.orientation, -s_hat_out));
    const std::complex<double> coefficient = gain * std::sqrt(length / (s_in * s_out)) *
                                             polarization_match(e_out, tag.polarization, tag.pose.orientation, s_hat_out);
    const std::complex<double> contribution = path_contribution(length, coefficient, f);
    // Level full: the edge's near field at an end close to it, beside its diffracted ray (same legs, same length).
    // It can matter where the ray itself is nothing (a tag's axis along the diffracted ray).
    const std::complex<double> near =
        includes(options_.level, ChannelLevel::kFull)
            ? near_field_coefficient(e, n, phi, phi_prime, sin_beta, va, vt, ant, tag, s_hat_in, s_in, length, k)
            : 0.0;
    const std::complex<double> near_contribution = path_contribution(length, near, f);
    const bool keep_ray = std::norm(contribution) >= floor, keep_near = std::norm(near_contribution) >= floor;
    if (!keep_ray && !keep_near) continue;  // would be dropped: no ray for it
    // Both legs clear, each shot from the edge (Embree works in float: the ray's origin is where its precision
    // matters, next to the faces that meet at the edge), starting and ending just off the edge and the ends.
    const double end_in = std::min(options_.endpoint_epsilon_m, 0.25 * s_in);
    const double end_out = std::min(options_.endpoint_epsilon_m, 0.25 * s_out);
    if (bvh.occluded(q, -s_hat_in, end_in, s_in - end_in)) continue;
    if (bvh.occluded(q, s_hat_out, end_out, s_out - end_out)) continue;
    TracedPath p;
    p.kind = PathKind::kDiffraction;
    p.length_m = length;
    p.point = q;
    p.material = facets[face0].material;
    p.facet = face0;
    p.edge = ei;
    p.coefficient = coefficient;
    p.contribution = contribution;
    if (keep_ray) out.push_back(p);
    if (!keep_near) continue;
    p.kind = PathKind::kEdgeNearField;
    p.coefficient = near;
    p.contribution = near_contribution;
    out.push_back(p);
  }
}

}  // namespace rfidray
