#pragma once
// The exact field of a perfectly conducting wedge lit by a plane wave: the eigenfunction (Bessel) series of the
// canonical problem (Bowman, Senior, Uslenghi, "Electromagnetic and Acoustic Scattering by Simple Shapes", 1969,
// ch. 6; Balanis, "Advanced Engineering Electromagnetics", 2nd ed., §13.3.1, eqs. 13-49 and 13-53, written here
// for the e^{jωt} convention of the whole project). Where UTD is an asymptotic expansion in 1/(kρ), the series
// converges fastest close to the edge (its terms fall off once the order ν exceeds kρ), so it is the reference
// that says how far UTD and plain geometrical optics are off a few centimetres from a wedge: core/level_validity.h
// uses it for the link's own angles.
//
// Edge-fixed coordinates as in core/utd.h: exterior angle nπ (n = 2: a half-plane, n = 3/2: a right-angled
// wedge, n = 1: an infinite plane), faces at φ = 0 and φ = nπ, 0 ≤ φ, φ' ≤ nπ. The incident field is the unit
// plane wave e^{jkρ cos(φ − φ')} travelling towards the edge from direction φ', normal to the edge; for oblique
// incidence at angle β0 to the edge pass k·sin β0 (the transverse problem; the axial phase is common to all
// terms). With ν_m = m/n:
//   soft (Dirichlet, E ∥ edge):   u = (4/n) Σ_{m≥1} j^{ν_m} J_{ν_m}(kρ) sin(ν_m φ') sin(ν_m φ)
//   hard (Neumann,  H ∥ edge):    u = (2/n) Σ_{m≥0} ε_m j^{ν_m} J_{ν_m}(kρ) cos(ν_m φ') cos(ν_m φ),  ε_0 = 1, ε_m = 2
// and for the hard case's electric field the same sums with ∂/∂ρ (J'_ν = (J_{ν−1} − J_{ν+1})/2) and ∂/∂φ.
// The sum stops once ν_m exceeds kρ by enough that the remaining terms are below 1e-15 (J_ν(x) < (x/2)^ν/Γ(ν+1)).
//
// Units: ρ in metres, k in rad/m, angles in radians. Pure functions: thread-safe. Throws std::invalid_argument
// for n outside [1, 2], kρ outside [0, 200] (the series needs ~n·kρ terms) or angles outside [0, nπ].
#include <complex>

namespace rfidray {

struct WedgeField {
  std::complex<double> soft;  // E_z / E^i_z (Dirichlet)
  std::complex<double> hard;  // H_z / H^i_z (Neumann)
  // The electric field of the hard case, E/(η H^i_z), in the edge's cylindrical components: from Ampère's law,
  // E_ρ = (1/(jkρ)) ∂H_z/∂φ and E_φ = −(1/(jk)) ∂H_z/∂ρ. Near the edge E_ρ grows as (kρ)^{−1/2} (the edge
  // condition, Meixner 1972), which no ray field has: each ray's E is transverse to the ray, and a diffracted ray
  // leaves the edge radially, so the ray fields carry E_ρ only through the incident and reflected plane waves.
  std::complex<double> hard_e_rho;
  std::complex<double> hard_e_phi;
};

// The total field (incident + scattered) at (ρ, φ), in units of the incident plane wave at the edge.
WedgeField wedge_plane_wave_exact(double n, double rho_m, double phi_rad, double phi_prime_rad, double wavenumber_rad_m);

// The same problem by geometrical optics (incident and face reflections, each on its lit side) and by GO plus
// Kouyoumjian–Pathak UTD (core/utd.h; L = ρ for a plane wave), as rfidray's levels compute it.
WedgeField wedge_plane_wave_geometrical_optics(double n, double rho_m, double phi_rad, double phi_prime_rad,
                                               double wavenumber_rad_m);
WedgeField wedge_plane_wave_utd(double n, double rho_m, double phi_rad, double phi_prime_rad, double wavenumber_rad_m);

}  // namespace rfidray
