// The exact wedge series (core/wedge_series.h) against the closed forms it must reduce to, and what it says
// about UTD and geometrical optics a few centimetres from an edge.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <stdexcept>

#include "core/units.h"
#include "core/wedge_series.h"
#include "tests/support/half_plane_exact.h"

namespace rfidray {
namespace {

using C = std::complex<double>;
constexpr double kDeg = kPi / 180.0;

// Largest |a − b| over observers all around the exterior of a wedge n (0.25° off each face), for one kρ and φ'.
template <typename F, typename G>
double worst_over_angles(double n, F&& a, G&& b, double* at_deg = nullptr) {
  double worst = 0.0;
  for (double phi_deg = 0.25; phi_deg < n * 180.0; phi_deg += 0.5) {
    const double e = std::abs(a(phi_deg * kDeg) - b(phi_deg * kDeg));
    if (e > worst) {
      worst = e;
      if (at_deg) *at_deg = phi_deg;
    }
  }
  return worst;
}

// n = 2 is the half-plane: the series must be Sommerfeld's closed form, close to the edge and far from it.
TEST(WedgeSeries, HalfPlaneIsSommerfeld) {
  const double k = wavenumber_rad_m(866e6);
  for (double krho : {0.2, 1.5, 6.0, 90.0})
    for (double phi_prime_deg : {30.0, 60.0, 100.0, 150.0})
      for (bool soft : {true, false}) {
        const double rho = krho / k, pp = phi_prime_deg * kDeg;
        const double worst = worst_over_angles(
            2.0,
            [&](double phi) {
              const WedgeField u = wedge_plane_wave_exact(2.0, rho, phi, pp, k);
              return soft ? u.soft : u.hard;
            },
            [&](double phi) { return testing::sommerfeld_half_plane(k, rho, phi, pp, soft); });
        EXPECT_LT(worst, 1e-9) << "kρ = " << krho << " φ' = " << phi_prime_deg << (soft ? " soft" : " hard");
      }
}

// n = 1 is an infinite plane: incident plus image, exactly.
TEST(WedgeSeries, PlaneIsIncidentPlusImage) {
  const double k = wavenumber_rad_m(866e6);
  for (double krho : {0.5, 4.0, 30.0})
    for (double phi_prime_deg : {20.0, 90.0, 160.0}) {
      const double rho = krho / k, pp = phi_prime_deg * kDeg;
      for (double phi_deg = 1.0; phi_deg < 180.0; phi_deg += 7.0) {
        const double phi = phi_deg * kDeg;
        const WedgeField u = wedge_plane_wave_exact(1.0, rho, phi, pp, k);
        const C inc = std::polar(1.0, krho * std::cos(phi - pp)), img = std::polar(1.0, krho * std::cos(phi + pp));
        EXPECT_LT(std::abs(u.soft - (inc - img)), 1e-10) << krho << " " << phi_prime_deg << " " << phi_deg;
        EXPECT_LT(std::abs(u.hard - (inc + img)), 1e-10) << krho << " " << phi_prime_deg << " " << phi_deg;
      }
    }
}

// The soft field vanishes on both faces of any wedge (Dirichlet), and the series stays bounded at the edge.
TEST(WedgeSeries, SoftFieldVanishesOnTheFaces) {
  const double k = wavenumber_rad_m(866e6);
  for (double n : {1.25, 1.5, 1.75})
    for (double krho : {0.3, 2.0, 10.0}) {
      const WedgeField on0 = wedge_plane_wave_exact(n, krho / k, 0.0, 50.0 * kDeg, k);
      const WedgeField onn = wedge_plane_wave_exact(n, krho / k, n * kPi, 50.0 * kDeg, k);
      EXPECT_LT(std::abs(on0.soft), 1e-12);
      EXPECT_LT(std::abs(onn.soft), 1e-12);
      EXPECT_LT(std::abs(on0.hard), 3.0);
    }
}

// Kouyoumjian–Pathak's UTD is exact for a half-plane under a plane wave (its transition function is the Fresnel
// integral of Sommerfeld's solution), at any distance from the edge: a tag 1 cm from a sheet's edge lit from far
// away is not outside UTD's range.
TEST(WedgeSeries, UtdIsExactForAHalfPlaneAtAnyDistance) {
  const double k = wavenumber_rad_m(866e6);
  for (double krho : {0.1, 0.5, 1.0, 3.0})
    for (double phi_prime_deg : {30.0, 60.0, 120.0})
      for (bool soft : {true, false}) {
        const double rho = krho / k, pp = phi_prime_deg * kDeg;
        const auto pick = [soft](const WedgeField& u) { return soft ? u.soft : u.hard; };
        const double worst = worst_over_angles(
            2.0, [&](double phi) { return pick(wedge_plane_wave_utd(2.0, rho, phi, pp, k)); },
            [&](double phi) { return pick(wedge_plane_wave_exact(2.0, rho, phi, pp, k)); });
        EXPECT_LT(worst, 1e-9) << "kρ = " << krho << " φ' = " << phi_prime_deg;
      }
}

// A right-angled wedge (a rack upright's corner, a box): UTD is asymptotic there, off by a share of the incident
// field close to the edge that shrinks as kρ grows; geometrical optics alone (no diffraction) is off by far more
// near the edge. These are the facts core/level_validity.h turns into a verdict; the figures are in
// docs/fullwave.md (bench/wedge_utd_error).
TEST(WedgeSeries, UtdErrorAtARightAngledWedgeShrinksAwayFromTheEdge) {
  const double k = wavenumber_rad_m(866e6), n = 1.5;
  double previous = 1e9;
  for (double krho : {0.25, 1.0, 4.0, 16.0}) {
    double utd_worst = 0.0, go_worst = 0.0;
    for (double phi_prime_deg : {20.0, 45.0, 70.0, 110.0, 135.0, 160.0, 200.0, 250.0})
      for (bool soft : {true, false}) {
        const double rho = krho / k, pp = phi_prime_deg * kDeg;
        const auto pick = [soft](const WedgeField& u) { return soft ? u.soft : u.hard; };
        const auto exact = [&](double phi) { return pick(wedge_plane_wave_exact(n, rho, phi, pp, k)); };
        utd_worst = std::max(utd_worst, worst_over_angles(n, [&](double phi) {
          return pick(wedge_plane_wave_utd(n, rho, phi, pp, k)); }, exact));
        go_worst = std::max(go_worst, worst_over_angles(n, [&](double phi) {
          return pick(wedge_plane_wave_geometrical_optics(n, rho, phi, pp, k)); }, exact));
      }
    EXPECT_LT(utd_worst, previous) << "kρ = " << krho;
    EXPECT_GT(go_worst, 2.0 * utd_worst) << "kρ = " << krho;
    previous = utd_worst;
  }
  EXPECT_LT(previous, 0.05);  // kρ = 16: UTD within 5 % of the incident field everywhere around the wedge
}

// The hard case's electric field is Ampère's law applied to H_z: checked against central differences of the
// series' own H_z in ρ and φ, and against incident + image on an infinite plane (n = 1).
TEST(WedgeSeries, HardElectricFieldIsAmperesLaw) {
  const double k = wavenumber_rad_m(866e6);
  const C j(0.0, 1.0);
  for (double n : {1.5, 2.0})
    for (double krho : {0.4, 1.5, 6.0})
      for (double phi_deg : {15.0, 100.0, 250.0}) {
        if (phi_deg >= n * 180.0) continue;
        const double rho = krho / k, phi = phi_deg * kDeg, pp = 50.0 * kDeg, h_rho = 1e-6 * rho, h_phi = 1e-6;
        const WedgeField u = wedge_plane_wave_exact(n, rho, phi, pp, k);
        const C d_rho = (wedge_plane_wave_exact(n, rho + h_rho, phi, pp, k).hard -
                         wedge_plane_wave_exact(n, rho - h_rho, phi, pp, k).hard) / (2.0 * h_rho);
        const C d_phi = (wedge_plane_wave_exact(n, rho, phi + h_phi, pp, k).hard -
                         wedge_plane_wave_exact(n, rho, phi - h_phi, pp, k).hard) / (2.0 * h_phi);
        EXPECT_LT(std::abs(u.hard_e_phi - (-d_rho / (j * k))), 1e-6) << n << " " << krho << " " << phi_deg;
        EXPECT_LT(std::abs(u.hard_e_rho - d_phi / (j * k * rho)), 1e-6) << n << " " << krho << " " << phi_deg;
      }
  const double rho = 2.0 / k;
  const WedgeField plane = wedge_plane_wave_exact(1.0, rho, 1.0, 0.5, k);
  const WedgeField images = wedge_plane_wave_geometrical_optics(1.0, rho, 1.0, 0.5, k);
  EXPECT_LT(std::abs(plane.hard_e_rho - images.hard_e_rho), 1e-12);
  EXPECT_LT(std::abs(plane.hard_e_phi - images.hard_e_phi), 1e-12);
}

// Across the edge (hard) ray optics misses the edge's radial near field: even on a half-plane, where UTD's H_z is
// exact, its electric field is off by a large share of the incident field close to the edge, shrinking as 1/√(kρ).
TEST(WedgeSeries, RayElectricFieldAcrossASheetEdgeMissesTheNearField) {
  const double k = wavenumber_rad_m(866e6), pp = 60.0 * kDeg;
  double previous = 1e9;
  for (double krho : {0.25, 1.0, 4.0, 16.0}) {
    const double rho = krho / k;
    double worst = 0.0;
    for (double phi_deg = 0.25; phi_deg < 360.0; phi_deg += 0.5) {
      const double phi = phi_deg * kDeg;
      const WedgeField e = wedge_plane_wave_exact(2.0, rho, phi, pp, k), u = wedge_plane_wave_utd(2.0, rho, phi, pp, k);
      EXPECT_LT(std::abs(u.hard - e.hard), 1e-9);  // H_z itself is exact
      worst = std::max(worst, std::hypot(std::abs(u.hard_e_rho - e.hard_e_rho), std::abs(u.hard_e_phi - e.hard_e_phi)));
    }
    EXPECT_LT(worst, previous) << "kρ = " << krho;
    previous = worst;
    if (krho < 1.0) {
      EXPECT_GT(worst, 0.5);
    }
  }
  EXPECT_LT(previous, 0.15);
}

TEST(WedgeSeries, RejectsWhatItCannotSum) {
  const double k = wavenumber_rad_m(866e6);
  EXPECT_THROW(wedge_plane_wave_exact(2.5, 0.1, 0.1, 0.1, k), std::invalid_argument);
  EXPECT_THROW(wedge_plane_wave_exact(1.5, 1e3, 0.1, 0.1, k), std::invalid_argument);
  EXPECT_THROW(wedge_plane_wave_exact(1.5, 0.1, 5.0, 0.1, k), std::invalid_argument);
  EXPECT_THROW(wedge_plane_wave_exact(1.5, std::nan(""), 0.1, 0.1, k), std::invalid_argument);
}

}  // namespace
}  // namespace rfidray
