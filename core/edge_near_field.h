#pragma once
// The near field of an edge, which no ray carries: the difference between the exact wedge (core/wedge_series.h)
// and geometrical optics + UTD for the canonical problem, added by level `full` to a link one of whose ends lies
// a few centimetres from an edge (raytrace/diffraction.cpp). Across the edge (hard, E ⊥ edge) the exact electric
// field has a radial part growing as (kρ)^−½ towards the edge (Meixner's edge condition); a ray's field is
// transverse to the ray, so GO + UTD miss it: 0.38 of the incident field at kρ = 0.73, 0.10 at kρ = 2.9 (median
// round a sheet's edge; the FDTD runs of bench/fullwave/ measure the same, docs/fullwave.md). Along the edge (soft)
// UTD is exact on a sheet and within 0.08 on a right-angled wedge down to kρ = 0.25, and the same correction makes
// it exact there too.
//
// The canonical problem is a plane wave at normal incidence on an infinite wedge: it holds for the end near the
// edge (distance ρ) when the other end is far (ρ' ≫ ρ) and the incidence is near normal (sin β0 → 1). The
// correction is weighted by how well that holds, w = w(kρ) · w(ρ'/ρ) · w(sin β0), each a smooth step (so h stays
// continuous as a tag moves):
//   w(kρ)     = 1 up to kρ = 6, 0 from kρ = 12 (where GO + UTD's own error is below ~0.01 median);
//   w(ρ'/ρ)   = 0 up to 3, 1 from 6 (the plane-wave error of the canonical problem is O(ρ/ρ'));
//   w(sin β0) = 0 up to 0.9, 1 from 0.97 (oblique incidence couples E_z and H_z, which the normal-incidence
//               correction leaves out; cos β0 ≤ 0.24 where it is applied in full).
// core/level_validity.h counts what the weights leave out as the level's error.
// Pure functions: thread-safe; nothing throws for finite input (angles are clamped into the wedge).
#include <complex>

namespace rfidray {

// exact − (GO + UTD) of the canonical problem, in units of the incident field at the edge: soft ΔE_z; hard the
// electric field's ΔE_ρ and ΔE_φ per unit η·H^i_z (core/wedge_series.h's WedgeField).
struct EdgeNearField {
  std::complex<double> soft;
  std::complex<double> hard_e_rho;
  std::complex<double> hard_e_phi;
};

EdgeNearField edge_near_field(double n, double rho_m, double phi_rad, double phi_prime_rad, double wavenumber_rad_m);

// The weight w above; 0 when the correction does not apply at all.
double edge_near_field_weight(double krho, double far_to_near_ratio, double sin_beta0);

// Beyond this kρ the correction is never applied (w(kρ) = 0).
inline constexpr double kEdgeNearFieldMaxKrho = 12.0;

}  // namespace rfidray
