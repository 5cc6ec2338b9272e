#pragma once
// Fresnel reflection/transmission at a planar boundary between air and a material with complex relative
// permittivity η (non-magnetic). θ is the angle of incidence from the surface normal.
// TE = E perpendicular to the plane of incidence ("s"), TM = E in the plane of incidence ("p").
// Sign convention for TM: Γ_TM = (η cosθ − √(η − sin²θ)) / (η cosθ + √(η − sin²θ)), so that both
// Γ_TE and Γ_TM → −1 at grazing incidence and Γ_TM = 0 at the Brewster angle of a lossless dielectric.
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
// Slab of thickness d (ITU-R P.2040 §2.2.3, multiple internal reflections summed): reflection R and
// transmission T amplitude coefficients, with T normalised so that a vanishing slab gives T = 1.
FresnelCoefficients slab_reflection(std::complex<double> eta, double cos_theta, double thickness_m, double frequency_hz);
FresnelCoefficients slab_transmission(std::complex<double> eta, double cos_theta, double thickness_m, double frequency_hz);

// Reflection for a material at a frequency: perfect conductor → {−1, +1·(sign per convention)},
// thickness > 0 → slab, else half-space.
FresnelCoefficients material_reflection(const RadioMaterial& m, double frequency_hz, double cos_theta);
// Transmission through one surface of the material (slab if thickness > 0; metal → 0).
FresnelCoefficients material_transmission(const RadioMaterial& m, double frequency_hz, double cos_theta);

// Reflects a polarized field vector travelling along `incident_dir` at a plane with unit `normal`:
// the TE component (along n × k̂) is scaled by Γ_TE, the TM component by Γ_TM and mapped onto the
// reflected wave's TM basis. Returns the field travelling along the reflected direction.
CVec3 reflect_field(const CVec3& field, const Vec3& incident_dir, const Vec3& normal, const FresnelCoefficients& gamma);
// Same for transmission straight through a surface (direction unchanged).
CVec3 transmit_field(const CVec3& field, const Vec3& dir, const Vec3& normal, const FresnelCoefficients& tau);

// Brewster angle (rad) of a lossless dielectric: tan θ_B = √ε'.
double brewster_angle_rad(double eps_r);

}  // namespace rfidray
