// Level full: first-order UTD edge diffraction at every edge of raytrace/edges.h (raytrace/path_finder.h has
// the physics, core/utd.h the coefficients), with the edge's near field (core/edge_near_field.h) at an end close
// to the edge. At a thin penetrable sheet's edge the incident shadow boundary's terms carry the jump incident −
// transmitted (the direct field goes on through the sheet as a `blocked` path), so that the field is continuous there.
//
// Level full-selective: the same, without the weakest diffracted paths, and with a bound on all it leaves out
// together. Every edge's contribution c_i is computed as in full (KP coefficient, gains, polarization), before
// any ray. The candidates are then taken strongest first, their legs' rays shot and h = (the paths found before
// diffraction) + (the diffractions kept) accumulated; the weakest remainder is left out as soon as the sum of
// its magnitudes is at most ε·|h| (ε = TraceOptions::diffraction_skipped_fraction; an edge's near field goes with
// its ray: one candidate, |c_ray| + |c_near|). Occlusion only removes a
// path, so the field left out is |h_full − h_selective| ≤ Σ|c_skipped| ≤ ε|h_selective| (before the drop floor,
// which both levels apply alike): |h_selective/h_full − 1| ≤ ε/(1 − ε), a round-trip phase error of at most
// 2·asin(ε/(1 − ε)) and an RSSI error of at most 40·log10(1/(1 − ε)) dB, whatever the number of edges. With the
// default ε = 0.02: 0.041 rad and 0.35 dB, inside `auto`'s tolerance (0.05 rad, 0.5 dB). A shadowed link (no
// path before diffraction, h = 0) keeps its strongest diffractions until the rest is within ε of them.
// What it saves is the two rays of each skipped edge, not its coefficient.
// (Before, a clear link skipped each edge more than N Fresnel zones from its boundaries on a per-edge bound;
// hundreds of such edges added up to 0.26 rad at p95 on the paper warehouse: docs/physics.md.)
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/edge_near_field.h"
#include "core/fresnel.h"
#include "core/units.h"
#include "core/utd.h"
#include "raytrace/diffraction_legs.h"
#include "raytrace/line_feet.h"
#include "raytrace/path_finder.h"

namespace rfidray {
namespace {

// A penetrable sheet at most this many wavelengths thick is thin: the field past its edge is the transmitted one
// right up to the edge (2 cm at 866 MHz: plasterboard, wood panels, glass; not a 20 cm concrete wall).
constexpr double kThinSheetWavelengths = 0.06;

// The received voltage of a near field `e` (not a ray: it may have a part along the arrival direction) at an
// antenna: a linear antenna takes the field along its axis (a short dipole's open-circuit voltage is l·E); others
// as a ray arriving along `arrival` (core/polarization.h).
std::complex<double> receive_near_field(const CVec3& e, const Endpoint& rx, const Vec3& arrival) {
  if (rx.polarization.kind == PolarizationKind::kLinear)
    return (rx.pose.orientation * rx.polarization.axis_local).cast<std::complex<double>>().dot(e);
  return polarization_match(e, rx.polarization, rx.pose.orientation, arrival);
}

// Levels full and full-selective: the edge's near field at whichever end is close to the edge (core/edge_near_field.h), a path of its
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

// An edge of full-selective waiting for its rays: |c_ray| + |c_near|, the diffracted path, its near field (a path
// of its own with the same legs), which of the two pass the drop floor, and the legs.
struct DiffractionCandidate {
  double magnitude = 0.0;
  double remaining = 0.0;  // magnitude + every weaker candidate's (set after sorting)
  TracedPath path;
  std::complex<double> near, near_contribution;
  bool keep_ray = false, keep_near = false;
  Vec3 s_hat_in;
  double s_in = 0.0;
  Vec3 s_hat_out;
  double s_out = 0.0;
};

// The diffracted ray and/or the edge's near field of one edge whose legs are clear.
void push_diffraction(TracedPath p, bool keep_ray, bool keep_near, std::complex<double> near,
                      std::complex<double> near_contribution, std::vector<TracedPath>& out) {
  if (keep_ray) out.push_back(p);
  if (!keep_near) return;
  p.kind = PathKind::kEdgeNearField;
  p.coefficient = near;
  p.contribution = near_contribution;
  out.push_back(p);
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
  // The levels that trace the direct path through walls (`blocked`): their diffraction scales the incident terms.
  const bool through_walls = includes(options_.level, ChannelLevel::kLosBlocked);
  // full-selective: candidates first, rays for the strongest (see the top of this file).
  const bool selective = !includes(options_.level, ChannelLevel::kFull);
  thread_local std::vector<DiffractionCandidate> tl_pending;  // per-thread scratch: no allocation once warm
  tl_pending.clear();
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
    if (posts_.post_of_edge[ei] != kNoPost) continue;  // a thin post's edges: its scattered field instead
    const Edge& e = edges_[ei];
    const Vec3& d = e.direction;
    // Feet of A and T on the edge's line and their distances from it.
    const LineFeet feet = line_feet(e.start, d, a, t);
    const Vec3& va = feet.v_a;
    const Vec3& vt = feet.v_t;
    const double rho_a = feet.rho_a, rho_t = feet.rho_t;
    if (rho_a < kOnEdge || rho_t < kOnEdge) continue;
    const double zq = fermat_point_z(feet);
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
    // The incident shadow boundary's terms compensate the direct field's jump across it. Past the edge of a thin
    // penetrable sheet the direct field goes on through it (a `blocked` path), so the jump is e_in − e_T, e_T the
    // field transmitted along the boundary ray as the direct path computes it (the sheet's slab transmission at
    // that incidence): geometrical optics plus diffraction then stays continuous there (the heuristic for a thin
    // dielectric slab's edge, Burnside & Burgener, IEEE Trans. AP 31(1), 1983). Only for a sheet thinner than
    // kThinSheetWavelengths·λ: past the edge of a thick wall the ray through the corner leaves by the wall's end
    // face (or is totally reflected inside it: concrete's critical angle is 26°), and FDTD finds the field on the
    // boundary an opaque edge's (0.50 of the free-space field beside a 20 cm concrete wall, which this heuristic
    // missed by 0.27, where the opaque edge is 0.11 off).
    // Metal, a half-space material (thickness 0) and solid wedges keep the opaque edge's jump, e_in.
    CVec3 e_out = -(dc.soft * e_beta) * beta_out.cast<std::complex<double>>() -
                  (dc.hard * e_phi) * phi_out.cast<std::complex<double>>();
    if (through_walls && n > 2.0 - 1e-9 && !m0.perfect_conductor && m0.thickness_m > 0.0 &&
        m0.thickness_m <= kThinSheetWavelengths * wavelength_m(f) && !m0.solid && options_.max_crossings >= 1) {
      // The incident terms' share of e_T given back: −D_inc·(e_in − e_T) = −D_inc·e_in + D_inc·e_T.
      const Facet& f0 = facets[face0];
      const CVec3 e_t = transmit_field(e_in, s_hat_in, f0.normal,
                                       material_transmission(m0, f, std::abs(s_hat_in.dot(f0.normal))));
      e_out += dc.incident * (beta_in.cast<std::complex<double>>().dot(e_t) * beta_out.cast<std::complex<double>>() +
                              phi_in.cast<std::complex<double>>().dot(e_t) * phi_out.cast<std::complex<double>>());
    }
    const double gain = std::sqrt(ant.pattern.gain_linear_world(ant.pose.orientation, s_hat_in) *
                                  tag.pattern.gain_linear_world(tag.pose.orientation, -s_hat_out));
    const std::complex<double> coefficient = gain * std::sqrt(length / (s_in * s_out)) *
                                             polarization_match(e_out, tag.polarization, tag.pose.orientation, s_hat_out);
    const std::complex<double> contribution = path_contribution(length, coefficient, f);
    // The edge's near field at an end close to it, beside its diffracted ray (same legs, same length). It can
    // matter where the ray itself is nothing (a tag's axis along the diffracted ray).
    const std::complex<double> near =
        near_field_coefficient(e, n, phi, phi_prime, sin_beta, va, vt, ant, tag, s_hat_in, s_in, length, k);
    const std::complex<double> near_contribution = path_contribution(length, near, f);
    const bool keep_ray = std::norm(contribution) >= floor, keep_near = std::norm(near_contribution) >= floor;
    if (!keep_ray && !keep_near) continue;  // would be dropped: no ray for it
    TracedPath p;
    p.kind = PathKind::kDiffraction;
    p.length_m = length;
    p.point = q;
    p.material = facets[face0].material;
    p.facet = face0;
    p.edge = ei;
    p.coefficient = coefficient;
    p.contribution = contribution;
    if (selective) {  // the ray and the near field share legs: one candidate, |c_ray| + |c_near|
      tl_pending.push_back({(keep_ray ? std::abs(contribution) : 0.0) + (keep_near ? std::abs(near_contribution) : 0.0),
                            0.0, p, near, near_contribution, keep_ray, keep_near, s_hat_in, s_in, s_hat_out, s_out});
      continue;
    }
    if (!legs_clear(bvh, q, s_hat_in, s_in, s_hat_out, s_out, options_.endpoint_epsilon_m)) continue;
    push_diffraction(p, keep_ray, keep_near, near, near_contribution, out);
  }
  if (!selective || tl_pending.empty()) return;
  // Strongest first (ties by edge index: the same order on every thread and run); remaining = Σ_{m ≥ j} |c_m|.
  std::sort(tl_pending.begin(), tl_pending.end(), [](const DiffractionCandidate& x, const DiffractionCandidate& y) {
    return x.magnitude != y.magnitude ? x.magnitude > y.magnitude : x.path.edge < y.path.edge;
  });
  double sum = 0.0;  // summed from the weakest up: each suffix sum is rounded once per term, not by subtraction
  for (auto c = tl_pending.rbegin(); c != tl_pending.rend(); ++c) c->remaining = sum += c->magnitude;
  std::complex<double> h{0.0, 0.0};
  for (size_t i = 0; i < found; ++i) h += out[i].contribution;
  const double fraction = options_.diffraction_skipped_fraction;
  for (const DiffractionCandidate& c : tl_pending) {
    if (c.remaining <= fraction * std::abs(h)) break;  // this one and all weaker, together, are within ε|h|
    if (!legs_clear(bvh, c.path.point, c.s_hat_in, c.s_in, c.s_hat_out, c.s_out, options_.endpoint_epsilon_m))
      continue;
    push_diffraction(c.path, c.keep_ray, c.keep_near, c.near, c.near_contribution, out);
    h += (c.keep_ray ? c.path.contribution : 0.0) + (c.keep_near ? c.near_contribution : 0.0);
  }
}

}  // namespace rfidray
