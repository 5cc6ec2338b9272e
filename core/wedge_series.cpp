#include "core/wedge_series.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/bessel_ladder.h"
#include "core/fresnel.h"
#include "core/units.h"
#include "core/utd.h"

namespace rfidray {
namespace {

using C = std::complex<double>;

// Ladders tried for the orders m/n: n = p/q with p ≤ 12 (every wedge whose interior angle is a multiple of 30° or
// 45°); other wedges take std::cyl_bessel_j per term.
constexpr int kMaxLadders = 12;

void check(double n, double rho_m, double phi_rad, double phi_prime_rad, double k) {
  const double krho = k * rho_m;
  if (!(n >= 1.0 && n <= 2.0)) throw std::invalid_argument("wedge series: n must be in [1, 2]");
  if (!(krho >= 0.0 && krho <= 200.0)) throw std::invalid_argument("wedge series: kρ must be in [0, 200]");
  const double top = n * kPi + 1e-12;
  if (!(phi_rad >= -1e-12 && phi_rad <= top && phi_prime_rad >= -1e-12 && phi_prime_rad <= top))
    throw std::invalid_argument("wedge series: angles must be in [0, nπ]");
}

}  // namespace

WedgeField wedge_plane_wave_exact(double n, double rho_m, double phi_rad, double phi_prime_rad, double k) {
  check(n, rho_m, phi_rad, phi_prime_rad, k);
  const double x = k * rho_m;
  const C j(0.0, 1.0);
  // m = 0 (hard only): ε_0 = 1, J'_0 = −J_1, and no φ dependence.
  WedgeField u{C(0.0), C((2.0 / n) * std::cyl_bessel_j(0.0, x)), C(0.0),
               j * (2.0 / n) * -std::cyl_bessel_j(1.0, x)};
  C sum_drho(0.0), sum_dphi(0.0);  // Σ of the hard terms differentiated in x and in φ (without the common factor)
  // Past ν ≈ x the terms fall faster than geometrically; ν = x + 30 + 4·x^{1/3} leaves < 1e-15 for x ≤ 200
  // (J_ν(x) ≤ (x/2)^ν/Γ(ν+1) and the Debye transition region is ~x^{1/3} wide).
  const double nu_max = x + 30.0 + 4.0 * std::cbrt(x);
  // When 1/n is a ratio q/p of small integers (a sheet: 1/2; a right-angled wedge: 2/3) the orders m/n = mq/p fall
  // on p unit ladders (core/bessel_ladder.h): J at every order from p direct evaluations instead of two per term.
  int p = 0, q = 0;
  for (int pp = 1; pp <= kMaxLadders && x > 0.0; ++pp) {
    const double qq = pp / n;
    if (std::abs(qq - std::round(qq)) <= 1e-12 * qq) {
      p = pp, q = static_cast<int>(std::round(qq));
      break;
    }
  }
  const int rungs = static_cast<int>(nu_max) + 3;  // orders up to ν_max + 1 (the derivative's J_{ν+1})
  thread_local std::vector<double> tl_ladders;      // ladder r at [r·rungs, (r + 1)·rungs): J_{r/p + i}(x)
  if (p > 0) {
    tl_ladders.resize(static_cast<size_t>(p) * rungs);
    for (int r = 0; r < p; ++r) bessel_j_ladder(static_cast<double>(r) / p, x, rungs, &tl_ladders[r * rungs]);
  }
  // J_{ν_m}(x) and J_{ν_m + 1}(x).
  const auto bessel = [&](int m, double nu, double& jn, double& jn1) {
    if (p > 0) {
      const int r = (m * q) % p, i = (m * q) / p;
      jn = tl_ladders[r * rungs + i];
      jn1 = tl_ladders[r * rungs + i + 1];
    } else {
      jn = std::cyl_bessel_j(nu, x);
      jn1 = std::cyl_bessel_j(nu + 1.0, x);
    }
  };
  for (int m = 1; m / n <= nu_max; ++m) {
    const double nu = p > 0 ? static_cast<double>(m * q) / p : m / n;
    double jn = 0.0, jn1 = 0.0;
    bessel(m, nu, jn, jn1);
    // Past ν = x, J_ν(x) falls monotonically and faster than geometrically: once a term is below 1e-16 of the
    // incident field the rest add less than that (and the derivative terms, ~(ν/x)·J_ν, follow within a few terms).
    if (nu > x + 2.0 && std::abs(jn) * std::max(1.0, nu / std::max(x, 1e-300)) < 1e-16) break;
    const C jnu = std::polar(1.0, kPi / 2.0 * nu);  // j^ν
    const double cos_source = std::cos(nu * phi_prime_rad);
    u.soft += (4.0 / n) * jnu * jn * std::sin(nu * phi_prime_rad) * std::sin(nu * phi_rad);
    u.hard += (4.0 / n) * jnu * jn * cos_source * std::cos(nu * phi_rad);
    // J'_ν(x) = (ν/x) J_ν(x) − J_{ν+1}(x) (DLMF 10.6.2): orders stay positive, which std::cyl_bessel_j needs.
    const double dj = x > 0.0 ? (nu / x) * jn - jn1 : (nu == 1.0 ? 0.5 : 0.0);
    sum_drho += (4.0 / n) * jnu * dj * cos_source * std::cos(nu * phi_rad);
    sum_dphi += (4.0 / n) * jnu * jn * cos_source * -nu * std::sin(nu * phi_rad);
  }
  u.hard_e_phi += j * sum_drho;                                   // −(1/(jk)) ∂/∂ρ = j ∂/∂x
  // (1/(jx)) ∂/∂φ. On the edge itself E_ρ is infinite for n > 1 (the edge condition): 0 is returned there.
  u.hard_e_rho = x > 0.0 ? sum_dphi / (j * x) : C(0.0);
  return u;
}

WedgeField wedge_plane_wave_geometrical_optics(double n, double rho_m, double phi_rad, double phi_prime_rad,
                                               double k) {
  check(n, rho_m, phi_rad, phi_prime_rad, k);
  const double x = k * rho_m;
  WedgeField u{C(0.0), C(0.0), C(0.0), C(0.0)};
  // A plane wave H_z = e^{jkρ cos(φ − α)} arriving from direction α has E/η = (−sin(φ − α), −cos(φ − α)) in
  // (ρ̂, φ̂): Ampère's law as for the series.
  const auto add = [&](double angle, double soft_sign) {
    const C w = std::polar(1.0, x * std::cos(angle));
    u.soft += soft_sign * w;
    u.hard += w;
    u.hard_e_rho += -std::sin(angle) * w;
    u.hard_e_phi += -std::cos(angle) * w;
  };
  if (std::abs(phi_rad - phi_prime_rad) < kPi) add(phi_rad - phi_prime_rad, 1.0);  // lit: not behind the wedge
  if (phi_rad + phi_prime_rad < kPi) add(phi_rad + phi_prime_rad, -1.0);          // face 0's reflection (α = −φ')
  // Face n's reflection (image at 2nπ − φ'); its boundary lies inside the exterior only when face n is lit.
  if (phi_rad > (2.0 * n - 1.0) * kPi - phi_prime_rad) add(phi_rad - (2.0 * n * kPi - phi_prime_rad), -1.0);
  return u;
}

WedgeField wedge_plane_wave_utd(double n, double rho_m, double phi_rad, double phi_prime_rad, double k) {
  WedgeField u = wedge_plane_wave_geometrical_optics(n, rho_m, phi_rad, phi_prime_rad, k);
  if (k * rho_m <= 0.0) return u;
  const FresnelCoefficients pec{C(-1.0, 0.0), C(1.0, 0.0)};
  // Plane wave: L = ρ (KP eq. 26 with s' → ∞, β0 = 90°); the diffracted ray leaves the edge as a cylindrical wave.
  // On (or within rounding of) a shadow boundary each UTD term takes the side geometrical optics took above, so
  // that GO + UTD is continuous there as the tracer's is (core/utd.h, GeometricOpticsSides).
  GeometricOpticsSides sides;
  sides.incident = std::abs(phi_rad - phi_prime_rad) < kPi ? 1 : -1;
  sides.reflected_face0 = phi_rad + phi_prime_rad < kPi ? 1 : -1;
  sides.reflected_facen = phi_rad > (2.0 * n - 1.0) * kPi - phi_prime_rad ? 1 : -1;
  sides.band_rad = 1e-9;
  const UtdCoefficients d = wedge_diffraction(n, phi_rad, phi_prime_rad, kPi / 2.0, rho_m, k, pec, pec, sides);
  const C spread = std::polar(1.0, -k * rho_m) / std::sqrt(rho_m);
  u.soft += d.soft * spread;
  u.hard += d.hard * spread;
  u.hard_e_phi += d.hard * spread;  // the diffracted ray leaves radially: its E is along φ̂ only (E_φ = η H_z)
  return u;
}

}  // namespace rfidray
