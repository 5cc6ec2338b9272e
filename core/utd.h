#pragma once
// Uniform geometrical theory of diffraction (UTD) at a straight wedge edge: the Kouyoumjian–Pathak diffraction
// coefficients (R. G. Kouyoumjian, P. H. Pathak, "A uniform geometrical theory of diffraction for an edge in a
// perfectly conducting surface", Proc. IEEE 62(11):1448–1461, 1974), with Luebbers' heuristic for wedges with
// lossy faces (R. J. Luebbers, "Finite conductivity uniform GTD versus knife edge diffraction in prediction of
// propagation path loss", IEEE Trans. Antennas Propag. 32(1):70–76, 1984). e^{jωt} convention, as everywhere.
//
// Edge-fixed coordinates: the wedge's exterior angle is nπ (n = 2: a half-plane, n = 3/2: a right-angled
// wedge); φ' and φ are the angles of the source and of the observer about the edge, measured from face 0
// through free space, 0 ≤ φ, φ' ≤ nπ; β0 is the angle between the incident ray and the edge (Keller's cone:
// the diffracted ray makes the same angle); L = s·s'·sin²β0/(s + s') for a spherical wave (s', s the distances
// source–edge and edge–observer). With the incident field E^i at the diffraction point Q, the diffracted field
// (KP eq. 23–27) is
//   E^d = −(D_s E^i_β0' β̂0 + D_h E^i_φ' φ̂) · √(s' / (s (s + s'))) · e^{−jks},
// D_s,h = −e^{−jπ/4} / (2n√(2πk) sin β0) · [ cot((π + β⁻)/2n) F(kL a⁺(β⁻)) + cot((π − β⁻)/2n) F(kL a⁻(β⁻))
//            + R_0 cot((π − β⁺)/2n) F(kL a⁻(β⁺)) + R_n cot((π + β⁺)/2n) F(kL a⁺(β⁺)) ],
// β^∓ = φ ∓ φ', a^±(β) = 2cos²((2nπN^± − β)/2) with N^± the integers nearest to satisfying 2nπN^± − β = ±π.
// For a perfect conductor R_0 = R_n = ∓1 (soft: E ∥ β̂0, upper sign; hard: lower sign) and this is KP's D.
// Luebbers: R_0, R_n are the faces' Fresnel coefficients (TE for soft, TM for hard, core/fresnel.h), R_0 at the
// incidence on face 0 (grazing angle φ') and R_n at the reflection off face n (grazing angle nπ − φ).
// Values only, no state: thread-safe, nothing throws.
#include <complex>

#include "core/fresnel.h"

namespace rfidray {

// ∫_a^∞ e^{−jτ²} dτ for real a ≥ 0 (a < 0 is taken as 0; fresnel_from_minus_infinity takes any a).
// Below a = 8: a Taylor series about tabulated nodes (core/utd.cpp), the nodes computed once by the power series
// (Abramowitz & Stegun 7.3.1 summed as one complex series) below a = 2 and the continued fraction of e^{z²}·erfc(z)
// (A&S 7.1.14) above; from a = 8 that continued fraction directly. ~1e-14 relative, checked against tabulated C, S.
// Thread-safe (the node table is a function-local static, built on first use).
std::complex<double> fresnel_tail(double a);
// ∫_{−∞}^a e^{−jτ²} dτ for any real a (Sommerfeld's half-plane integral).
std::complex<double> fresnel_from_minus_infinity(double a);
// KP's transition function F(X) = 2j√X e^{jX} ∫_{√X}^∞ e^{−jτ²} dτ, X ≥ 0 (X < 0 is taken as 0).
// F → 1 for X → ∞ (away from shadow boundaries UTD becomes Keller's GTD), F ~ √(πX) e^{jπ/4} for X → 0.
std::complex<double> utd_transition(double x);

struct UtdCoefficients {
  std::complex<double> soft;  // D_s, m^½: E component along β̂ (E ∥ edge at β0 = 90°)
  std::complex<double> hard;  // D_h, m^½: E component along φ̂
  // The incident shadow boundary's two terms alone, part of both soft and hard (the same for either): what
  // compensates the direct field's jump there. Past a thin penetrable sheet's edge the direct field does not
  // vanish but goes on transmitted, so a caller scales this part by the jump, incident − transmitted
  // (raytrace/diffraction.cpp).
  std::complex<double> incident;
};

// Which side of its shadow boundary the tracer put each geometrical-optics field, for an observer on or within
// `band_rad` of that boundary. Each term of D jumps by exactly the field its boundary switches on or off (the
// part cot(u)·j√(πX)·e^{jX}·e^{−jπ/4} of cot(u)·F(X), odd in the angle δ from the boundary), so the total is
// continuous only if the term takes the same side as the geometrical-optics path: on a boundary the direct or
// reflected ray grazes the edge and the tracer decides in float (Embree) whether it is blocked, which the
// angles computed in double cannot foresee. +1: the field is there (the lit side, δ > 0), −1: it is not,
// 0: take the side from the angles (as outside the band).
struct GeometricOpticsSides {
  int incident = 0;         // the direct path (terms 1, 2: boundary φ = φ' ± π)
  int reflected_face0 = 0;  // the reflection off face 0 (boundary φ = π − φ')
  int reflected_facen = 0;  // the reflection off face n (boundary φ = (2n − 1)π − φ')
  double band_rad = 0.0;    // within this angle of a boundary the sides above decide
};

// D_s and D_h as above. `face0`, `facen`: Fresnel coefficients of face 0 at grazing angle φ' and of face n at
// grazing angle nπ − φ (perfect conductor: {−1, +1}); te multiplies the soft, tm the hard reflected terms.
// n in [1, 2]; wavenumber k > 0, L > 0, 0 < β0 < π. A cot term whose argument sits on its pole is replaced
// by its finite limit (KP eq. 29), so the result is finite on the shadow boundaries; within `sides.band_rad`
// of a boundary the term takes the side `sides` gives (the other side's continuation: the term minus twice
// its jumping part), so that geometrical optics plus diffraction is continuous whatever the tracer decided.
UtdCoefficients wedge_diffraction(double n, double phi_rad, double phi_prime_rad, double beta0_rad,
                                  double distance_parameter_m, double wavenumber_rad_m,
                                  const FresnelCoefficients& face0, const FresnelCoefficients& facen,
                                  const GeometricOpticsSides& sides = {});

// The smallest argument X = kL·a of the four transition functions of wedge_diffraction (same n, φ, φ' and
// kL = wavenumber × distance parameter): how far, in the transition function's own measure, the observer is
// from the nearest incident or reflection shadow boundary. X = π·N² at N Fresnel-zone widths √(λ/L) (angle
// δ from the boundary: a ≈ δ²/2, so X ≈ kLδ²/2 = π(δ/√(λ/L))²). Each term of D, relative to the free-space
// field λ/(4π(s + s')) of the diffracted ray, is at most |F(X)|/(2√(πX)) (|cot x| ≤ 1/|x| on |x| ≤ π/2 and
// 2|sin(δ/2)| ≤ |δ|), so an edge whose smallest X is large contributes little: 4 terms at X ≥ π·3² give at most
// 0.21 of that free-space field, typically far less.
double utd_min_transition_argument(double n, double phi_rad, double phi_prime_rad, double kl);

}  // namespace rfidray
