// Bessel ladders by backward recurrence (core/bessel_ladder.h) against the standard library's direct evaluation,
// and the wedge series that uses them against the direct evaluation per term.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/bessel_ladder.h"
#include "core/units.h"
#include "core/wedge_series.h"

namespace rfidray {
namespace {

TEST(BesselLadder, MatchesDirectEvaluationOnEveryRung) {
  // The fractional parts the wedge series uses (sheets 1/2; right angles 1/3, 2/3; 45° wedges quarters) and others.
  for (double nu0 : {0.0, 1.0 / 3.0, 0.5, 2.0 / 3.0, 0.25, 0.75, 0.123}) {
    for (double x : {1e-3, 0.05, 0.7, 3.0, 12.0, 55.5, 200.0}) {
      const int count = static_cast<int>(x + 30.0 + 4.0 * std::cbrt(x)) + 3;
      std::vector<double> j(count);
      bessel_j_ladder(nu0, x, count, j.data());
      double largest = 0.0;
      for (int r = 0; r < count; ++r) largest = std::max(largest, std::abs(std::cyl_bessel_j(nu0 + r, x)));
      for (int r = 0; r < count; ++r) {
        const double direct = std::cyl_bessel_j(nu0 + r, x);
        // Relative to the ladder's largest value (what a sum over the ladder needs), and relative to itself
        // wherever it is not tiny (a term's own accuracy).
        EXPECT_LE(std::abs(j[r] - direct), 1e-12 * largest) << "nu " << nu0 + r << " x " << x;
        if (std::abs(direct) > 1e-200) EXPECT_LE(std::abs(j[r] - direct), 1e-9 * std::abs(direct)) << "nu " << nu0 + r << " x " << x;
      }
    }
  }
}

TEST(BesselLadder, RefusesWhatItCannotEvaluate) {
  double out[2];
  EXPECT_THROW(bessel_j_ladder(0.5, 0.0, 2, out), std::invalid_argument);
  EXPECT_THROW(bessel_j_ladder(0.5, std::nan(""), 2, out), std::invalid_argument);
  EXPECT_THROW(bessel_j_ladder(-0.5, 1.0, 2, out), std::invalid_argument);
  EXPECT_THROW(bessel_j_ladder(0.5, 1.0, -1, out), std::invalid_argument);
}

// The series with its ladders equals the series summed with a direct evaluation per term: n = 1.75 (a 45° wedge,
// on seven ladders) against n = 1.75 + 1e-7 (no ladder: every term direct), which moves each term by ~1e-7·ν
// relative, so the two agree to that, and a sheet and a right angle likewise.
TEST(BesselLadder, WedgeSeriesOnLaddersEqualsTheSeriesTermByTerm) {
  const double k = 2.0 * kPi / 0.3463;
  for (double n : {2.0, 1.5, 1.75}) {
    for (double rho : {0.004, 0.02, 0.08, 0.3}) {
      for (double phi : {0.3, 1.9, 3.5}) {
        const double phi_prime = 0.8;
        if (phi > n * kPi) continue;
        const WedgeField on_ladders = wedge_plane_wave_exact(n, rho, phi, phi_prime, k);
        const WedgeField direct = wedge_plane_wave_exact(n - 1e-7, rho, phi, phi_prime, k);
        const double tol = 2e-5;  // the 1e-7 shift in n, carried through ~k·ρ + 40 terms
        EXPECT_LT(std::abs(on_ladders.soft - direct.soft), tol) << n << " " << rho << " " << phi;
        EXPECT_LT(std::abs(on_ladders.hard - direct.hard), tol) << n << " " << rho << " " << phi;
        EXPECT_LT(std::abs(on_ladders.hard_e_rho - direct.hard_e_rho), tol * std::max(1.0, 1.0 / std::sqrt(k * rho)));
        EXPECT_LT(std::abs(on_ladders.hard_e_phi - direct.hard_e_phi), tol);
      }
    }
  }
}

}  // namespace
}  // namespace rfidray
