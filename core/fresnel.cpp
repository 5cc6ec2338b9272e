#include "core/fresnel.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/units.h"

namespace rfidray {
namespace {

using C = std::complex<double>;

double clamp_cos(double cos_theta) { return std::clamp(std::abs(cos_theta), 0.0, 1.0); }

// √(η − sin²θ) = √η·cos θ_t, principal branch: Re ≥ 0 and, for a lossy η (Im η < 0), Im ≤ 0, so the
// refracted wave e^{−j k0 √(η − sin²θ) z} decays into the material (e^{jωt} convention).
C refracted_root(C eta, double c) { return std::sqrt(eta - (1.0 - c * c)); }

// TE unit vector ŝ ∝ n × k̂ (perpendicular to the plane of incidence). At normal incidence the plane of
// incidence is undefined; any ŝ ⟂ n works because then Γ_TM = −Γ_TE (so the result does not depend on it).
Vec3 te_axis(const Vec3& n, const Vec3& k) {
  Vec3 s = n.cross(k);
  const double len = s.norm();
  if (len > 1e-12) return s / len;
  const Vec3 helper = std::abs(n.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return n.cross(helper).normalized();
}

}  // namespace

FresnelCoefficients fresnel_reflection(std::complex<double> eta, double cos_theta) {
  const double c = clamp_cos(cos_theta);
  const C root = refracted_root(eta, c);
  return {(c - root) / (c + root), (eta * c - root) / (eta * c + root)};
}

FresnelCoefficients fresnel_transmission(std::complex<double> eta, double cos_theta) {
  const double c = clamp_cos(cos_theta);
  const C root = refracted_root(eta, c);
  // E-field ratios; TM in the basis ŝ × k̂ of each medium. TM from H continuity: E_t/E_i = (H_t/H_i)/√η.
  return {2.0 * c / (c + root), 2.0 * std::sqrt(eta) * c / (eta * c + root)};
}

// ITU-R P.2040 §2.2.3: a slab of thickness d in air, all internal reflections summed.
// q = (2π d/λ)·√(η − sin²θ) is the phase (and loss) across the slab; R' the half-space coefficient.
//   R = R'·(1 − e^{−j2q}) / (1 − R'²·e^{−j2q})
//   T = (1 − R'²)·e^{−j(q − q0)} / (1 − R'²·e^{−j2q}),  q0 = (2π d/λ)·cos θ
// T is relative to free-space propagation along the same straight line (the caller's e^{−jk0 L} already
// covers the slab's thickness as if it were air; e^{+j q0} removes that part), so η = 1 or d = 0 give T = 1.
FresnelCoefficients slab_reflection(std::complex<double> eta, double cos_theta, double thickness_m,
                                    double frequency_hz) {
  const double c = clamp_cos(cos_theta);
  const FresnelCoefficients r = fresnel_reflection(eta, c);
  const C q = kTwoPi * std::max(thickness_m, 0.0) / wavelength_m(frequency_hz) * refracted_root(eta, c);
  const C e2 = std::exp(C(0, -2) * q);
  auto slab = [&](C rp) { return rp * (1.0 - e2) / (1.0 - rp * rp * e2); };
  return {slab(r.te), slab(r.tm)};
}

FresnelCoefficients slab_transmission(std::complex<double> eta, double cos_theta, double thickness_m,
                                      double frequency_hz) {
  const double c = clamp_cos(cos_theta);
  const FresnelCoefficients r = fresnel_reflection(eta, c);
  const double k0d = kTwoPi * std::max(thickness_m, 0.0) / wavelength_m(frequency_hz);
  const C q = k0d * refracted_root(eta, c);
  const double q0 = k0d * c;
  const C e2 = std::exp(C(0, -2) * q);
  const C e1 = std::exp(C(0, -1) * (q - q0));
  auto slab = [&](C rp) { return (1.0 - rp * rp) * e1 / (1.0 - rp * rp * e2); };
  return {slab(r.te), slab(r.tm)};
}

FresnelCoefficients material_reflection(const RadioMaterial& m, double frequency_hz, double cos_theta) {
  // Perfect conductor: tangential E vanishes → Γ_TE = −1; tangential H doubles → Γ_TM = +1 (H-ratio convention).
  if (m.perfect_conductor) return {C(-1.0, 0.0), C(1.0, 0.0)};
  const C eta = m.complex_permittivity(frequency_hz);
  if (m.thickness_m > 0.0) return slab_reflection(eta, cos_theta, m.thickness_m, frequency_hz);
  return fresnel_reflection(eta, cos_theta);
}

FresnelCoefficients material_transmission(const RadioMaterial& m, double frequency_hz, double cos_theta) {
  if (m.perfect_conductor) return {C(0.0, 0.0), C(0.0, 0.0)};
  const C eta = m.complex_permittivity(frequency_hz);
  if (m.thickness_m > 0.0) return slab_transmission(eta, cos_theta, m.thickness_m, frequency_hz);
  return fresnel_transmission(eta, cos_theta);
}

CVec3 reflect_field(const CVec3& field, const Vec3& incident_dir, const Vec3& normal, const FresnelCoefficients& gamma) {
  const Vec3 k = incident_dir.normalized();
  Vec3 n = normal.normalized();
  if (k.dot(n) > 0.0) n = -n;  // the normal faces the incoming wave
  const Vec3 k_r = k - 2.0 * k.dot(n) * n;
  const Vec3 s = te_axis(n, k);
  const Vec3 p_i = s.cross(k), p_r = s.cross(k_r);
  const C e_s = s.cast<C>().dot(field);  // Eigen's dot conjugates the first argument; s is real
  const C e_p = p_i.cast<C>().dot(field);
  return gamma.te * e_s * s.cast<C>() + gamma.tm * e_p * p_r.cast<C>();
}

CVec3 transmit_field(const CVec3& field, const Vec3& dir, const Vec3& normal, const FresnelCoefficients& tau) {
  const Vec3 k = dir.normalized();
  Vec3 n = normal.normalized();
  if (k.dot(n) > 0.0) n = -n;
  const Vec3 s = te_axis(n, k);
  const Vec3 p = s.cross(k);
  const C e_s = s.cast<C>().dot(field);
  const C e_p = p.cast<C>().dot(field);
  return tau.te * e_s * s.cast<C>() + tau.tm * e_p * p.cast<C>();
}

double brewster_angle_rad(double eps_r) {
  if (!(std::isfinite(eps_r) && eps_r > 0.0))
    throw InputError("brewster_angle_rad: relative permittivity must be finite and > 0 (got " +
                     std::to_string(eps_r) + ")");
  return std::atan(std::sqrt(eps_r));
}

}  // namespace rfidray
