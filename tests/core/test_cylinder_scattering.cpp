// The cylinder series (core/cylinder_scattering.h) against what defines it: the boundary condition on the
// conductor (the incident field in closed form, H0^(2)(k|ρ − ρ'|), independent of the series), the thin-wire limit
// of its n = 0 coefficient, and the library Bessel functions its asymptotic Hankel expansion replaces far out.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <random>
#include <stdexcept>

#include "core/cylinder_scattering.h"
#include "core/units.h"

namespace rfidray {
namespace {

using C = std::complex<double>;

C hankel0(double x) { return C(std::cyl_bessel_j(0.0, x), -std::cyl_neumann(0.0, x)); }

// The incident field of the line source at (xs, 0) at the observer (xo, φ), both in units of 1/k.
C incident(double xs, double xo, double phi) {
  return hankel0(std::sqrt(xs * xs + xo * xo - 2.0 * xs * xo * std::cos(phi)));
}

TEST(CylinderScattering, SoftFieldVanishesOnTheConductor) {
  for (double ka : {0.05, 0.54, 1.8, 6.0}) {
    const CylinderCoefficients c = cylinder_coefficients(ka);
    // Down to ρ' = 1.6a: the series is cut at kCylinderMaxTerms, whose last term is (a/ρ')^48 ~ 1e-10 there.
    for (double xs : {1.6 * ka, 3.0 * ka + 1.0, 27.7, 180.0}) {
      const CylinderCoefficients c = cylinder_coefficients(ka, cylinder_terms(ka, xs, ka));
      for (double phi = 0.0; phi < kTwoPi; phi += 0.37) {
        const C total = incident(xs, ka, phi) + cylinder_scattered(c, CylinderPolarization::kSoft, xs, ka, phi);
        EXPECT_LT(std::abs(total), 1e-9 * std::abs(incident(xs, ka, phi)) + 1e-12)
            << "ka " << ka << " k rho' " << xs << " phi " << phi;
      }
    }
  }
}

TEST(CylinderScattering, HardFieldHasNoNormalDerivativeOnTheConductor) {
  // ∂/∂(kρ) of incident + scattered at kρ = ka, one-sided second order from ka, ka + h, ka + 2h.
  for (double ka : {0.2, 0.9, 3.0}) {
    const double h = 1e-4 * ka;
    for (double xs : {2.0 * ka + 0.5, 27.7}) {
      const CylinderCoefficients c = cylinder_coefficients(ka, cylinder_terms(ka, xs, ka));
      for (double phi = 0.1; phi < kTwoPi; phi += 0.61) {
        const auto total = [&](double x) {
          return incident(xs, x, phi) + cylinder_scattered(c, CylinderPolarization::kHard, xs, x, phi);
        };
        const C derivative = (-3.0 * total(ka) + 4.0 * total(ka + h) - total(ka + 2.0 * h)) / (2.0 * h);
        const C incident_derivative =
            (-3.0 * incident(xs, ka, phi) + 4.0 * incident(xs, ka + h, phi) - incident(xs, ka + 2.0 * h, phi)) / (2.0 * h);
        // The finite difference's own error is O(h²) of the second derivative: ~1e-7 of the field here.
        EXPECT_LT(std::abs(derivative), 2e-6 * (std::abs(incident_derivative) + std::abs(incident(xs, ka, phi))))
            << "ka " << ka << " k rho' " << xs << " phi " << phi;
      }
    }
  }
}

TEST(CylinderScattering, ThinWireLimitOfTheFirstCoefficient) {
  // ka → 0: J_0 → 1, Y_0 → (2/π)(ln(ka/2) + γ), so c_0 → −1 / (1 − j(2/π)(ln(ka/2) + γ)) (Harrington §5.10).
  constexpr double kEulerGamma = 0.5772156649015329;
  for (double ka : {1e-3, 1e-2}) {
    const C expected = -1.0 / C(1.0, -(2.0 / kPi) * (std::log(ka / 2.0) + kEulerGamma));
    EXPECT_LT(std::abs(cylinder_coefficients(ka).soft[0] - expected), 1e-3 * std::abs(expected)) << ka;
  }
}

TEST(CylinderScattering, HankelExpansionMatchesTheBesselFunctionsWhereItTakesOver) {
  // From x = max(30, 2·count²) hankel2_orders uses Hankel's expansion; the library's Bessel functions there.
  for (double x : {30.0, 33.0, 50.0, 200.0}) {
    C h[4];
    hankel2_orders(x, 4, h);
    for (int n = 0; n < 4; ++n) {
      const C exact(std::cyl_bessel_j(n, x), -std::cyl_neumann(n, x));
      EXPECT_LT(std::abs(h[n] - exact), 1e-8 * std::abs(exact)) << "n " << n << " x " << x;
    }
  }
  // Miller's J_n against the library, below and above the order's turning point.
  for (double x : {0.03, 0.9, 7.5, 29.0}) {
    double j[20];
    bessel_j_orders(x, 20, j);
    for (int n = 0; n < 20; ++n)
      EXPECT_NEAR(j[n], std::cyl_bessel_j(n, x), 1e-14 + 1e-12 * std::abs(std::cyl_bessel_j(n, x))) << n << " " << x;
  }
  // And the far form of H_0 used to map two dimensions to three.
  EXPECT_LT(std::abs(hankel2_zero_far(400.0) - hankel0(400.0)), 1e-3 * std::abs(hankel0(400.0)));
}

TEST(CylinderScattering, NeumannSeriesGivesTheLibrarysBesselFunctionsOfTheSecondKind) {
  // Below x = 300 hankel2_orders takes Y_0, Y_1 from Neumann's series over one Miller ladder, then recurs upwards;
  // above, the library's. Every order against the library, on both sides of the switch, near zeros of J_0 (where a
  // Wronskian would divide by ~0) and at the thin-wire end.
  for (double x : {1e-3, 0.02, 0.5, 2.404825557695773, 5.520078110286311, 9.0, 17.3, 29.9, 44.0, 120.0, 299.9, 300.1}) {
    C h[12];
    hankel2_orders(x, 12, h, 13);  // 13 significant orders: the Bessel functions up to x = 338, not the expansion
    for (int n = 0; n < 12; ++n) {
      const double y = std::cyl_neumann(n, x);
      EXPECT_NEAR(-h[n].imag(), y, 1e-13 * std::max(1.0, std::abs(y))) << "n " << n << " x " << x;
      EXPECT_NEAR(h[n].real(), std::cyl_bessel_j(n, x), 1e-13) << "n " << n << " x " << x;
    }
  }
}

TEST(CylinderScattering, ForwardScatteringOfAThickCylinderCastsAShadow) {
  // A cylinder of ka = 6 lit from far away: straight behind it, close to it, the total field is far below the
  // incident one; to the side (90°, lit) it is not.
  const double xs = 400.0, xo = 7.0;
  const CylinderCoefficients c = cylinder_coefficients(6.0, cylinder_terms(6.0, xs, xo));
  const double behind = std::abs(incident(xs, xo, kPi) + cylinder_scattered(c, CylinderPolarization::kSoft, xs, xo, kPi));
  const double side =
      std::abs(incident(xs, xo, kPi / 2) + cylinder_scattered(c, CylinderPolarization::kSoft, xs, xo, kPi / 2));
  EXPECT_LT(behind, 0.35 * std::abs(incident(xs, xo, kPi)));
  EXPECT_GT(side, 0.5 * std::abs(incident(xs, xo, kPi / 2)));
}

TEST(CylinderScattering, RefusesWhatItCannotSum) {
  EXPECT_THROW(cylinder_coefficients(0.0), std::invalid_argument);
  EXPECT_THROW(cylinder_coefficients(kCylinderMaxKa * 1.01), std::invalid_argument);
  EXPECT_THROW(cylinder_coefficients(std::nan("")), std::invalid_argument);
}

// The bound raytrace/post_scattering.cpp skips posts by: never below the series, for cylinders up to its ka_max and
// ends from kCylinderBoundMinX out — including ka_max past the zeros where |c_n| stops growing (it takes 1 there) —
// and not so loose that it would skip nothing: within a factor 2 of the largest value the series reaches for a thin
// post.
TEST(CylinderScattering, BoundHoldsForEveryThinnerCylinderAndFartherEnd) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const double ka_max : {0.02, 0.3, 0.6, 0.85, 0.95, 1.5, 3.0}) {
    const CylinderScatteringBound bound(ka_max);
    double worst_soft = 0.0, worst_hard = 0.0;  // the largest share of each bound the series reaches
    for (int i = 0; i < 3000; ++i) {
      const double ka = ka_max * (i % 3 == 0 ? 1.0 : std::max(1e-3, unit(rng)));
      const double xs = kCylinderBoundMinX * std::pow(200.0, unit(rng));
      const double xo = i % 5 == 0 ? kCylinderBoundMinX : kCylinderBoundMinX * std::pow(200.0, unit(rng));
      const double phi = 2.0 * kPi * unit(rng);
      const CylinderCoefficients c = cylinder_coefficients(ka, cylinder_terms(ka, xs, xo));
      const CylinderField u = cylinder_scattered(c, xs, xo, phi);
      const double far = std::abs(hankel2_zero_far(xs + xo));
      const CylinderBoundRatios limit = bound.ratio(xs, xo);
      ASSERT_LE(std::abs(u.soft) / far, limit.soft) << ka_max << " " << ka << " " << xs << " " << xo << " " << phi;
      ASSERT_LE(std::abs(u.hard) / far, limit.hard) << ka_max << " " << ka << " " << xs << " " << xo << " " << phi;
      worst_soft = std::max(worst_soft, std::abs(u.soft) / far / limit.soft);
      worst_hard = std::max(worst_hard, std::abs(u.hard) / far / limit.hard);
    }
    if (ka_max <= 0.85) {
      EXPECT_GT(worst_soft, 0.5) << ka_max;  // 0.82–0.99 when written
      EXPECT_GT(worst_hard, 0.5) << ka_max;
    }
  }
}

TEST(CylinderScattering, BoundRestsOnCoefficientsThatGrowWithKa) {
  // The claim the bound takes C_n = |c_n(ka_max)| from (core/cylinder_scattering.h), on a fine grid: soft n = 0
  // below 0.8935, soft n ≥ 1 and hard n = 0 below 2.197, hard n ≥ 1 below n.
  for (int n = 0; n < 6; ++n) {
    const double soft_limit = n == 0 ? 0.8935 : std::max(2.1971, static_cast<double>(n));
    const double hard_limit = n == 0 ? 2.1971 : static_cast<double>(n);
    double last_soft = 0.0, last_hard = 0.0;
    for (double ka = 0.002; ka < std::max(soft_limit, hard_limit); ka += 0.002) {
      const CylinderCoefficients c = cylinder_coefficients(ka, n + 2);
      if (ka < soft_limit) {
        EXPECT_GE(std::abs(c.soft[n]), last_soft) << n << " " << ka;
        last_soft = std::abs(c.soft[n]);
      }
      if (ka < hard_limit) {
        EXPECT_GE(std::abs(c.hard[n]), last_hard) << n << " " << ka;
        last_hard = std::abs(c.hard[n]);
      }
    }
  }
}

TEST(CylinderScattering, BoundSaysNothingCloserThanItsRange) {
  const CylinderScatteringBound bound(0.5);
  EXPECT_TRUE(std::isinf(bound.ratio(kCylinderBoundMinX * 0.99, 100.0).soft));
  EXPECT_TRUE(std::isinf(bound.ratio(100.0, std::nan("")).hard));
  EXPECT_TRUE(std::isfinite(bound.ratio(kCylinderBoundMinX, kCylinderBoundMinX).soft));
  EXPECT_TRUE(std::isinf(CylinderScatteringBound().ratio(100.0, 100.0).hard));
  EXPECT_THROW(CylinderScatteringBound(0.0), std::invalid_argument);
  EXPECT_THROW(CylinderScatteringBound(kCylinderMaxKa * 1.01), std::invalid_argument);
}

}  // namespace
}  // namespace rfidray
