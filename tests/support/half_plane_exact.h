#pragma once
// Sommerfeld's exact solution for a plane wave on a perfectly conducting half-plane (Born & Wolf, Principles of
// Optics, §11.5), the closed form the diffraction tests check against. With the incident field e^{jkρ cos(φ − φ')}
// (unit at the edge, e^{jωt}) and
//   V(ρ, ξ) = e^{jkρ cos ξ} · e^{jπ/4}/√π · ∫_{−∞}^{√(2kρ) cos(ξ/2)} e^{−jτ²} dτ,
// the total field is u = V(ρ, φ − φ') ∓ V(ρ, φ + φ') (soft: E ∥ edge, u = 0 on the screen; hard: H ∥ edge).
// The Fresnel integral is core/utd.h's, checked against tabulated values in tests/core/test_utd.cpp.
#include <cmath>
#include <complex>

#include "core/units.h"
#include "core/utd.h"

namespace rfidray::testing {

inline std::complex<double> sommerfeld_half_plane(double k, double rho, double phi, double phi_prime, bool soft) {
  auto v = [&](double xi) {
    return std::polar(1.0, k * rho * std::cos(xi)) * std::polar(1.0, kPi / 4.0) / std::sqrt(kPi) *
           fresnel_from_minus_infinity(std::sqrt(2.0 * k * rho) * std::cos(xi / 2.0));
  };
  return v(phi - phi_prime) + (soft ? -1.0 : 1.0) * v(phi + phi_prime);
}

}  // namespace rfidray::testing
