// The reflected Sommerfeld kernels of a dielectric half-space (core/dielectric_half_space.h) against the limits
// they must reach in closed form: a perfect conductor (the image), a half-space of air (nothing), and the
// electrostatic image −(ε − 1)/(ε + 1) of a charge close to a dielectric. The dipole beside water and a low-loss
// dielectric is checked against NEC-2's Sommerfeld ground in tests/core/test_tag_antenna.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "core/dielectric_half_space.h"
#include "core/error.h"
#include "core/thin_wire_dipole.h"
#include "core/units.h"

namespace rfidray {
namespace {

constexpr double kFrequency_hz = 866e6;
using C = std::complex<double>;

C image_kernel(double rho_m, double distance_m) {
  const double k = kTwoPi * kFrequency_hz / kSpeedOfLight_m_s;
  const double r = std::hypot(rho_m, 2.0 * distance_m);
  return std::exp(C(0.0, -k * r)) / (4.0 * kPi * r);
}

// ε = 10⁹(1 − j) (σ = 4.8·10⁷ S/m, about copper's): |R_TE + 1| ≈ 2|k_z|/|k_z1| with |k_z1| = √|ε| k₀ ≈ 7·10⁵ /m
// and the spectrum reaching k_ρ ~ 1/(2d) (170 /m at 3 mm), so both kernels are the negated image to ~5·10⁻⁴, from
// the near field (ρ ≪ 2d) to the far field (ρ ≫ λ). (At ε = 10⁷(1 − j) the same test sees 0.5 %: the physics of a
// conductor with a 25 µm skin depth, not a numerical error.)
TEST(DielectricHalfSpace, GoodConductorIsThePerfectImage) {
  const C eps(1e9, -1e9);
  for (double d : {0.003, 0.01, 0.05}) {
    for (double rho : {0.0, 0.001, 0.01, 0.05, 0.166, 0.5}) {
      const HalfSpaceKernelValue v = half_space_reflected_kernel(rho, d, kFrequency_hz, eps);
      const C image = -image_kernel(rho, d);
      EXPECT_LE(std::abs(v.vector - image), 2e-3 * std::abs(image)) << "d " << d << " rho " << rho << ": " << v.vector;
      EXPECT_LE(std::abs(v.scalar - image), 2e-3 * std::abs(image)) << "d " << d << " rho " << rho << ": " << v.scalar;
    }
  }
}

TEST(DielectricHalfSpace, AirReflectsNothing) {
  for (double rho : {0.0, 0.01, 0.1}) {
    const HalfSpaceKernelValue v = half_space_reflected_kernel(rho, 0.01, kFrequency_hz, C(1.0, 0.0));
    EXPECT_LE(std::abs(v.vector), 1e-9 * std::abs(image_kernel(rho, 0.01)));
    EXPECT_LE(std::abs(v.scalar), 1e-9 * std::abs(image_kernel(rho, 0.01)));
  }
}

// A charge 0.2 mm from a lossless dielectric (2d√ε k₀ ≤ 0.07 up to ε = 80): the scalar kernel is the
// electrostatic image charge −(ε − 1)/(ε + 1) to O(2d√ε k₀); the vector kernel (currents, which a non-magnetic
// medium images only through the spectrum below √ε k₀) is far smaller. (At 1 mm from water, 2d√ε k₀ = 0.3 and
// the vector kernel is already 0.16 of the scalar one: 1 mm from water is not quasi-static.)
TEST(DielectricHalfSpace, NearFieldIsTheElectrostaticImage) {
  const double d = 0.0002;
  for (double eps : {2.0, 4.0, 80.0}) {
    const double expected_factor = -(eps - 1.0) / (eps + 1.0);
    const HalfSpaceKernelValue v = half_space_reflected_kernel(0.0, d, kFrequency_hz, C(eps, 0.0));
    const C image = image_kernel(0.0, d);
    EXPECT_NEAR((v.scalar / image).real(), expected_factor, 0.05 * std::abs(expected_factor)) << "eps " << eps;
    EXPECT_LT(std::abs(v.vector), 0.1 * std::abs(v.scalar)) << "eps " << eps;
  }
}

// The tabulated kernel (interpolated in ρ) gives the same dipole impedance as the perfect conductor's image in
// closed form when the medium is a good conductor: the table, its interpolation and the segment integrals.
TEST(DielectricHalfSpace, DipoleOnAGoodConductorMatchesTheImagePlane) {
  const ThinWireDipole dipole{0.166, 0.0005};
  for (double d : {0.005, 0.05}) {
    const auto plane = perfect_conductor_plane(d, kFrequency_hz);
    const auto half_space = dielectric_half_space(d, kFrequency_hz, C(1e9, -1e9), dipole.length_m);
    const C z_plane = dipole_input_impedance(dipole, kFrequency_hz, plane.get());
    const C z_half_space = dipole_input_impedance(dipole, kFrequency_hz, half_space.get());
    // 1 % of |Z| plus 0.05 Ω: near resonance |Z| is a few ohms, and the copper-like plane's own surface loss
    // (R_s = 8 mΩ) adds a few hundredths of an ohm to R that the perfect image has not.
    EXPECT_LE(std::abs(z_half_space - z_plane), 0.01 * std::abs(z_plane) + 0.05)
        << "d " << d << ": half-space " << z_half_space << ", image " << z_plane;
  }
}

TEST(DielectricHalfSpace, BadInputThrows) {
  EXPECT_THROW(dielectric_half_space(0.0, kFrequency_hz, C(2.0, 0.0), 0.2), InputError);
  EXPECT_THROW(dielectric_half_space(0.01, -1.0, C(2.0, 0.0), 0.2), InputError);
  EXPECT_THROW(dielectric_half_space(0.01, kFrequency_hz, C(0.5, 0.0), 0.2), InputError);
  EXPECT_THROW(dielectric_half_space(0.01, kFrequency_hz, C(2.0, 1.0), 0.2), InputError);  // gain, not loss
  EXPECT_THROW(dielectric_half_space(0.01, kFrequency_hz, C(2.0, 0.0), 0.0), InputError);
  EXPECT_THROW(dielectric_half_space(0.01, kFrequency_hz, C(std::nan(""), 0.0), 0.2), InputError);
}

}  // namespace
}  // namespace rfidray
