// UTD (core/utd.h): the Fresnel integral against tabulated values, the transition function's limits, and the
// Kouyoumjian–Pathak half-plane coefficients against Sommerfeld's exact half-plane solution.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>

#include "core/units.h"
#include "core/utd.h"
#include "tests/support/half_plane_exact.h"

namespace rfidray {
namespace {

using C = std::complex<double>;

// ∫_0^a e^{−jτ²} dτ = √(π/2)·(C(x) − j S(x)), x = a√(2/π), with C, S the standard Fresnel integrals.
C head_from_table(double x_standard, double c, double s) {
  (void)x_standard;
  return std::sqrt(kPi / 2.0) * C(c, -s);
}

TEST(Utd, FresnelIntegralMatchesTabulatedValues) {
  // C(x), S(x) (Abramowitz & Stegun Table 7.7; 10 digits).
  struct Row {
    double x, c, s;
  };
  const Row rows[] = {{0.5, 0.4923442259, 0.0647324329},
                      {1.0, 0.7798934004, 0.4382591474},
                      {1.5, 0.4452611760, 0.6975049601},
                      {2.0, 0.4882534061, 0.3434156784},
                      {3.0, 0.6057207893, 0.4963129990},
                      {4.5, 0.5260259151, 0.4342729751}};
  const C whole = 0.5 * std::sqrt(kPi) * std::polar(1.0, -kPi / 4.0);  // ∫_0^∞ e^{−jτ²} dτ
  for (const Row& r : rows) {
    const double a = r.x * std::sqrt(kPi / 2.0);
    const C expected_tail = whole - head_from_table(r.x, r.c, r.s);
    EXPECT_LT(std::abs(fresnel_tail(a) - expected_tail), 2e-10) << "x = " << r.x;
    EXPECT_LT(std::abs(fresnel_from_minus_infinity(a) - (whole + head_from_table(r.x, r.c, r.s))), 2e-10);
    EXPECT_LT(std::abs(fresnel_from_minus_infinity(-a) - expected_tail), 2e-10);
  }
  // The series / continued-fraction switch at a = 2 is seamless: a step h across it changes the tail by
  // h·e^{−ja²} (its derivative) and nothing more.
  const double h = 1e-7;
  EXPECT_LT(std::abs(fresnel_tail(2.0 - h) - fresnel_tail(2.0) - h * std::polar(1.0, -4.0)), 1e-13);
}

// An independent check of the tail by brute-force quadrature (composite Simpson on [a, 60] plus the
// asymptotic remainder e^{−jb²}/(2jb)), at many points on both sides of the switch.
TEST(Utd, FresnelTailMatchesQuadrature) {
  for (double a : {0.0, 0.3, 1.1, 1.99, 2.01, 2.7, 4.0, 7.5}) {
    const double b = 60.0;
    const int n = 400000;
    const double h = (b - a) / n;
    C sum = std::polar(1.0, -a * a) + std::polar(1.0, -b * b);
    for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * std::polar(1.0, -(a + i * h) * (a + i * h));
    C quad = sum * h / 3.0;
    // ∫_b^∞ e^{−jτ²} dτ ≈ e^{−jb²}/(2jb)·(1 − 1/(2jb²)) (integration by parts, twice).
    quad += std::polar(1.0, -b * b) / C(0.0, 2.0 * b) * (1.0 - 1.0 / C(0.0, 2.0 * b * b));
    EXPECT_LT(std::abs(fresnel_tail(a) - quad), 1e-9) << "a = " << a;
  }
}

TEST(Utd, TransitionFunctionLimits) {
  // Large X: F → 1 + j/(2X) − 3/(4X²) (KP eq. 30).
  for (double x : {20.0, 100.0, 1e4}) {
    const C expected = 1.0 + C(0.0, 1.0) / (2.0 * x) - 3.0 / (4.0 * x * x);
    EXPECT_LT(std::abs(utd_transition(x) - expected), 2.0 / (x * x * x)) << x;
  }
  // Small X: F ≈ [√(πX) − 2X e^{jπ/4} − (2/3)X² e^{−jπ/4}] e^{j(π/4 + X)} (KP eq. 31).
  for (double x : {1e-6, 1e-4, 1e-3}) {
    const C expected = (std::sqrt(kPi * x) - 2.0 * x * std::polar(1.0, kPi / 4.0) -
                        2.0 / 3.0 * x * x * std::polar(1.0, -kPi / 4.0)) *
                       std::polar(1.0, kPi / 4.0 + x);
    EXPECT_LT(std::abs(utd_transition(x) - expected), 5.0 * std::pow(x, 2.5)) << x;
  }
  EXPECT_EQ(utd_transition(0.0), C(0.0, 0.0));
}

// Below X = 64 F comes from Taylor series about nodes 0.05 apart in √X (core/utd.cpp): the series of two
// neighbouring nodes meet at the midpoint between them, and the series meets the continued fraction at √X = 8,
// to 1e-14 — a wrong derivative recurrence or node value would open a gap there (and fail the tables above).
TEST(Utd, TransitionFunctionIsContinuousWhereItsEvaluationChanges) {
  // Across 2h the tail ∫_a^∞ e^{−jτ²}dτ itself changes by −e^{−ja²}·2h; what is left is the gap.
  const double h = 1e-9;
  auto gap = [&](double a) {
    return std::abs(fresnel_tail(a + h) - fresnel_tail(a - h) + std::polar(2.0 * h, -a * a));
  };
  for (int i = 0; i < 160; ++i) {
    const double a = 0.05 * (i + 0.5);
    EXPECT_LT(gap(a), 1e-14) << "a = " << a;
  }
  EXPECT_LT(gap(8.0), 1e-14);
  EXPECT_LT(gap(2.0), 1e-14);
}

// The continued fraction's depth falls with X (core/utd.cpp); at every X from 25 up, F(X) equals its asymptotic
// series Σ_k (2k − 1)!! (j/2X)^k summed to its smallest term (error below that term: ≤ 4e-11 at X = 25,
// ≤ 2e-15 from X = 40, < 1e-40 from X = 100), over a fine grid that crosses every change of depth.
TEST(Utd, TransitionFunctionEqualsItsAsymptoticSeriesWhereTheDepthFalls) {
  for (double x = 25.0; x < 4e4; x *= 1.002) {
    C sum = 1.0, term = 1.0;
    double smallest = 1.0;
    for (int k = 1; k < 400; ++k) {
      const C next = term * C(0.0, (2.0 * k - 1.0) / (2.0 * x));
      if (std::abs(next) >= smallest) break;
      term = next;
      smallest = std::abs(term);
      sum += term;
    }
    EXPECT_LT(std::abs(utd_transition(x) - sum), std::max(4.0 * smallest, 3e-15)) << "X = " << x;
  }
}

C sommerfeld(double k, double rho, double phi, double phi_prime, bool soft) {
  return testing::sommerfeld_half_plane(k, rho, phi, phi_prime, soft);
}

// UTD: geometrical optics (incident where |φ − φ'| < π, reflected off the face φ = 0 where φ + φ' < π, with
// Γ = −1 soft, +1 hard) plus the diffracted field D·e^{−jkρ}/√ρ (plane wave: L = ρ).
C utd_total(double k, double rho, double phi, double phi_prime, bool soft) {
  C u = 0.0;
  if (std::abs(phi - phi_prime) < kPi) u += std::polar(1.0, k * rho * std::cos(phi - phi_prime));
  if (phi + phi_prime < kPi) u += (soft ? -1.0 : 1.0) * std::polar(1.0, k * rho * std::cos(phi + phi_prime));
  const FresnelCoefficients pec{C(-1.0, 0.0), C(1.0, 0.0)};
  const UtdCoefficients d = wedge_diffraction(2.0, phi, phi_prime, kPi / 2.0, rho, k, pec, pec);
  return u + (soft ? d.soft : d.hard) * std::polar(1.0, -k * rho) / std::sqrt(rho);
}

// For a half-plane lit by a plane wave, KP's UTD reproduces Sommerfeld's solution exactly (the Fresnel
// integral of the exact solution is the transition function): lit region, both transition regions (incident
// and reflection shadow boundaries) and the shadow, at ρ = 5 m and 866 MHz (kρ ≈ 91).
TEST(Utd, HalfPlaneMatchesSommerfeldEverywhere) {
  const double k = wavenumber_rad_m(866e6), rho = 5.0;
  double worst = 0.0;
  for (bool soft : {true, false})
    for (double phi_prime_deg : {30.0, 60.0, 100.0, 150.0})
      for (double phi_deg = 0.25; phi_deg < 360.0; phi_deg += 0.5) {
        const double phi = phi_deg * kPi / 180.0, phi_prime = phi_prime_deg * kPi / 180.0;
        const C exact = sommerfeld(k, rho, phi, phi_prime, soft);
        const C utd = utd_total(k, rho, phi, phi_prime, soft);
        worst = std::max(worst, std::abs(utd - exact));
        ASSERT_LT(std::abs(utd - exact), 1e-9) << (soft ? "soft" : "hard") << " φ' = " << phi_prime_deg
                                               << "° φ = " << phi_deg << "°";
      }
  EXPECT_LT(worst, 1e-9);
}

// Across each shadow boundary the diffracted field jumps by exactly the geometrical-optics field it replaces,
// so the total is continuous: a step of 1e-7 rad across the boundary changes u by ~kρ·1e-7.
TEST(Utd, TotalFieldIsContinuousAcrossShadowBoundaries) {
  const double k = wavenumber_rad_m(866e6), rho = 5.0, phi_prime = 60.0 * kPi / 180.0;
  for (bool soft : {true, false})
    for (double boundary : {kPi + phi_prime, kPi - phi_prime}) {  // incident, reflection shadow boundary
      const C below = utd_total(k, rho, boundary - 1e-7, phi_prime, soft);
      const C above = utd_total(k, rho, boundary + 1e-7, phi_prime, soft);
      EXPECT_LT(std::abs(above - below), 1e-4) << (soft ? "soft" : "hard") << " at " << boundary;
      EXPECT_GT(std::abs(below), 0.3);  // ~half the incident field on the boundary, not a null
    }
}

// The tracer decides in float whether a ray grazing an edge is blocked; GeometricOpticsSides lets the diffracted
// field take that side. The total (geometrical optics as the tracer found it + diffraction) must be continuous
// whichever side the geometric optics was put on, within the band: here the direct and the reflected field are
// switched on the "wrong" side of their boundary (1e-7 rad beyond it) and D told so.
TEST(Utd, ForcedSideKeepsTheTotalContinuous) {
  const double k = wavenumber_rad_m(866e6), rho = 5.0, phi_prime = 60.0 * kPi / 180.0;
  const FresnelCoefficients pec{C(-1.0, 0.0), C(1.0, 0.0)};
  for (bool soft : {true, false}) {
    const double isb = kPi + phi_prime, rsb = kPi - phi_prime;
    auto total = [&](double phi, bool direct, bool reflected, GeometricOpticsSides sides) {
      C u = 0.0;
      if (direct) u += std::polar(1.0, k * rho * std::cos(phi - phi_prime));
      if (reflected) u += (soft ? -1.0 : 1.0) * std::polar(1.0, k * rho * std::cos(phi + phi_prime));
      const UtdCoefficients d = wedge_diffraction(2.0, phi, phi_prime, kPi / 2.0, rho, k, pec, pec, sides);
      return u + (soft ? d.soft : d.hard) * std::polar(1.0, -k * rho) / std::sqrt(rho);
    };
    const double band = 1e-4;
    // Incident boundary: beyond it (φ > φ' + π) the direct path is "found" anyway.
    const C lit = total(isb - 1e-7, true, false, {});
    const C forced = total(isb + 1e-7, true, false, {1, -1, -1, band});
    EXPECT_LT(std::abs(forced - lit), 1e-4) << (soft ? "soft" : "hard");
    // Without the side, the same total is off by the whole incident field.
    EXPECT_GT(std::abs(total(isb + 1e-7, true, false, {}) - lit), 0.9);
    // Exactly on the boundary, both sides give the same total with their own geometrical optics.
    EXPECT_LT(std::abs(total(isb, true, false, {1, -1, -1, band}) - total(isb, false, false, {-1, -1, -1, band})), 1e-9);
    // Reflection boundary: the reflection missed on the lit side (φ < π − φ').
    const C with = total(rsb + 1e-7, true, false, {});
    const C missed = total(rsb - 1e-7, true, false, {1, -1, -1, band});
    EXPECT_LT(std::abs(missed - with), 1e-4) << (soft ? "soft" : "hard");
    // Outside the band the side is ignored.
    EXPECT_EQ(total(isb + 0.01, false, false, {1, 1, 1, band}), total(isb + 0.01, false, false, {}));
  }
}

// Luebbers' form with perfectly conducting faces is KP's; with lossy faces the reflection-boundary terms
// are scaled by the faces' Fresnel coefficients, the incident-boundary terms are not.
TEST(Utd, LuebbersReducesToKpForMetal) {
  const double k = wavenumber_rad_m(866e6);
  const FresnelCoefficients pec{C(-1.0, 0.0), C(1.0, 0.0)};
  const UtdCoefficients kp = wedge_diffraction(1.5, 2.0, 0.7, 1.2, 3.0, k, pec, pec);
  EXPECT_TRUE(std::isfinite(std::abs(kp.soft)) && std::isfinite(std::abs(kp.hard)));
  const FresnelCoefficients none{C(0.0, 0.0), C(0.0, 0.0)};
  const UtdCoefficients inc = wedge_diffraction(1.5, 2.0, 0.7, 1.2, 3.0, k, none, none);
  EXPECT_EQ(inc.soft, inc.hard);  // only the incident-boundary terms left: polarization-independent
  EXPECT_NE(kp.soft, kp.hard);
}

// The criterion of level full-selective (core/utd.h, utd_min_transition_argument): X = kL·2sin²(δ/2) at an
// angle δ from the nearest boundary (π·N² at N Fresnel zones for small δ), and the bound it rests on: with
// β0 = 90°, |D|/√L ≤ Σ over the four terms of |F(X_i)|/(2√(πX_i)) ≤ 2·1.001/√(πX_min) once X_min ≥ 9π
// (|F(X)| − 1 < 1e-3 there), for metal faces (|R| = 1) over a grid of wedges, angles and distances.
TEST(Utd, MinTransitionArgumentAndTheBoundOutsideTheTransitionRegion) {
  const double k = wavenumber_rad_m(866e6);
  // Half-plane, source at φ' = 60°: incident shadow boundary at 240°, reflection boundary at 120°.
  const double phi_prime = kPi / 3.0, kl = k * 2.0;
  for (double delta_deg : {0.5, 2.0, 10.0, 30.0}) {
    const double delta = delta_deg * kPi / 180.0;
    EXPECT_NEAR(utd_min_transition_argument(2.0, phi_prime + kPi - delta, phi_prime, kl),
                kl * 2.0 * std::pow(std::sin(delta / 2.0), 2), 1e-9 * kl);
    EXPECT_NEAR(utd_min_transition_argument(2.0, kPi - phi_prime + delta, phi_prime, kl),
                kl * 2.0 * std::pow(std::sin(delta / 2.0), 2), 1e-9 * kl);
  }
  // N Fresnel zones √(λ/L) from the boundary: X → π·N² as the zone shrinks (large kL).
  const double big_kl = 1e6, zone = std::sqrt(kTwoPi / big_kl);
  EXPECT_NEAR(utd_min_transition_argument(2.0, phi_prime + kPi - 3.0 * zone, phi_prime, big_kl), 9.0 * kPi, 1e-3);
  int checked = 0;
  for (double n : {1.25, 1.5, 1.75, 2.0})
    for (double l : {0.5, 2.0, 8.0, 30.0})
      for (double pp = 2.0; pp < 180.0 * n; pp += 17.0)
        for (double p = 1.0; p < 180.0 * n; p += 7.0) {
          const double phi = p * kPi / 180.0, phip = pp * kPi / 180.0;
          const double x = utd_min_transition_argument(n, phi, phip, k * l);
          if (x < 9.0 * kPi) continue;
          const UtdCoefficients d = wedge_diffraction(n, phi, phip, kPi / 2.0, l, k, {-1.0, 1.0}, {-1.0, 1.0});
          const double bound = 2.0 * 1.001 / std::sqrt(kPi * x);
          EXPECT_LE(std::abs(d.soft) / std::sqrt(l), bound) << n << " " << l << " " << pp << " " << p;
          EXPECT_LE(std::abs(d.hard) / std::sqrt(l), bound) << n << " " << l << " " << pp << " " << p;
          ++checked;
        }
  EXPECT_GT(checked, 500);
}

// The same bound at any distance from the boundaries (|F(X)| < 1 for every X > 0; the edge-end check of
// raytrace/edge_end_finder.h skips an edge's coefficients with it): every term of D is at most 1/(2√(πX)) of the
// diffracted ray's free-space field, so max(|D_s|, |D_h|)·sin β₀/√L ≤ 2/√(π X_min), for perfect conductors and for
// lossy faces (|R| ≤ 1), at any β₀.
TEST(Utd, TermBoundHoldsAtEveryTransitionArgument) {
  const double k = wavenumber_rad_m(866e6);
  const FresnelCoefficients lossy{std::complex<double>(-0.6, 0.2), std::complex<double>(0.3, -0.5)};
  int checked = 0;
  for (double n : {1.1, 1.25, 1.5, 1.75, 2.0})
    for (double l : {0.01, 0.1, 0.5, 2.0, 30.0})
      for (double beta_deg : {20.0, 90.0, 150.0})
        for (double pp = 0.5; pp < 180.0 * n; pp += 13.0)
          for (double p = 0.3; p < 180.0 * n; p += 2.9) {
            const double phi = p * kPi / 180.0, phip = pp * kPi / 180.0, beta = beta_deg * kPi / 180.0;
            const double x = utd_min_transition_argument(n, phi, phip, k * l);
            if (!(x > 1e-9)) continue;
            const double bound = 2.0 * 1.001 / std::sqrt(kPi * x);
            for (const FresnelCoefficients& r : {FresnelCoefficients{-1.0, 1.0}, lossy}) {
              const UtdCoefficients d = wedge_diffraction(n, phi, phip, beta, l, k, r, r);
              const double scale = std::sin(beta) / std::sqrt(l);
              EXPECT_LE(std::abs(d.soft) * scale, bound) << n << " " << l << " " << pp << " " << p << " " << x;
              EXPECT_LE(std::abs(d.hard) * scale, bound) << n << " " << l << " " << pp << " " << p << " " << x;
            }
            ++checked;
          }
  EXPECT_GT(checked, 20000);
}

}  // namespace
}  // namespace rfidray
