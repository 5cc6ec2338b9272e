#pragma once
// Fresnel reflection/transmission at a planar boundary between air and a material with complex relative
// permittivity η (non-magnetic, e^{jωt} convention, Im η ≤ 0 for loss). θ is the angle of incidence from the
// surface normal; functions take cos θ and use |cos θ| clamped to [0, 1] (either side of the surface).
//
// Conventions (as in ITU-R P.2040):
//  TE = E perpendicular to the plane of incidence ("s"), along ŝ = n × k̂ / |n × k̂|.
//  TM = E in the plane of incidence ("p"). Γ_TM is the ratio of the (tangential) H fields, H ∥ ŝ:
//     Γ_TE = (cosθ − √(η − sin²θ)) / (cosθ + √(η − sin²θ)),
//     Γ_TM = (η cosθ − √(η − sin²θ)) / (η cosθ + √(η − sin²θ)),
//  so both → −1 at grazing incidence and Γ_TM = 0 at the Brewster angle of a lossless dielectric.
//  The TM field basis that goes with it is p̂ = ŝ × k̂ for each wave (incident, reflected, transmitted):
//  E = Z·H × k̂ puts a TM wave with H = H_s ŝ at E = Z·H_s p̂, hence E_p,r = Γ_TM·E_p,i.
//  At normal incidence Γ_TM = −Γ_TE = (√η − 1)/(√η + 1) and p̂_r = −p̂_i, so the reflected field vector is
//  (1 − √η)/(1 + √η) times the incident one for every polarization (a PEC mirror returns −E).
//  Perfect conductor: Γ_TE = −1, Γ_TM = +1 (tangential E cancels, tangential H doubles), transmission 0.
//  Half-space transmission coefficients are E-field ratios (TM in the basis ŝ × k̂ of each medium):
//     T_TE = 2cosθ / (cosθ + √(η − sin²θ)),  T_TM = 2√η cosθ / (η cosθ + √(η − sin²θ)),
//  and for a lossless half-space |Γ|² + Re(√(η − sin²θ)/cosθ)·|T|² = 1.
#include <complex>

#include "core/geometry.h"
#include "core/material.h"
#include "core/polarization.h"

namespace rfidray {

struct FresnelCoefficients {
  std::complex<double> te;
  std::complex<double> tm;
};

// Half-space (infinitely thick) interface.
FresnelCoefficients fresnel_reflection(std::complex<double> eta, double cos_theta);
FresnelCoefficients fresnel_transmission(std::complex<double> eta, double cos_theta);
// Slab of thickness d in air (ITU-R P.2040 §2.2.3, multiple internal reflections summed): reflection R
// (referred to the front face) and transmission T amplitude coefficients. T is relative to free-space
// propagation over the same straight line, so a vanishing slab (d = 0) or η = 1 gives T = 1 and R = 0;
// a thick lossy slab tends to the half-space reflection. The same coefficients hold for E and H (air on
// both sides). thickness_m < 0 is treated as 0.
FresnelCoefficients slab_reflection(std::complex<double> eta, double cos_theta, double thickness_m, double frequency_hz);
FresnelCoefficients slab_transmission(std::complex<double> eta, double cos_theta, double thickness_m, double frequency_hz);

// Reflection for a material at a frequency: perfect conductor → {−1, +1}, thickness > 0 → slab, else half-space.
FresnelCoefficients material_reflection(const RadioMaterial& m, double frequency_hz, double cos_theta);
// Transmission through one surface of the material: slab if thickness > 0 (the usual blocked-path model);
// thickness 0 → the air→material half-space interface coefficient; metal → 0.
FresnelCoefficients material_transmission(const RadioMaterial& m, double frequency_hz, double cos_theta);

// Reflects a polarized field vector travelling along `incident_dir` at a plane with unit `normal`:
// the TE component (along ŝ = n × k̂) is scaled by Γ_TE, the TM component (along ŝ × k̂_i) by Γ_TM and mapped
// onto the reflected wave's TM basis ŝ × k̂_r. Returns the field travelling along the reflected direction
// k̂_r = k̂ − 2(k̂·n)n. The normal may point either way. Any longitudinal part of `field` is dropped.
CVec3 reflect_field(const CVec3& field, const Vec3& incident_dir, const Vec3& normal, const FresnelCoefficients& gamma);
// Same for transmission straight through a surface (direction unchanged; TM basis ŝ × k̂ on both sides).
CVec3 transmit_field(const CVec3& field, const Vec3& dir, const Vec3& normal, const FresnelCoefficients& tau);

// Brewster angle (rad) of a lossless dielectric: tan θ_B = √ε'. Throws InputError unless ε' > 0 and finite.
double brewster_angle_rad(double eps_r);

}  // namespace rfidray
