#include "core/cylinder_scattering.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/units.h"

namespace rfidray {
namespace {

using C = std::complex<double>;

// Hankel's expansion of H_n^(2)(x), A&S 9.2.5–9.2.10: √(2/πx) (P − jQ) e^{−jχ}, χ = x − (n/2 + 1/4)π,
// P = Σ_{k even} (−1)^{k/2} a_k, Q = Σ_{k odd} (−1)^{(k−1)/2} a_k, a_k = Π_{m=1}^{k} (4n² − (2m − 1)²) / (k! (8x)^k).
C hankel2_expansion(int n, double x) {
  const double mu = 4.0 * n * n;
  double a = 1.0, p = 1.0, q = 0.0;
  for (int k = 1; k <= 6; ++k) {
    a *= (mu - (2.0 * k - 1.0) * (2.0 * k - 1.0)) / (k * 8.0 * x);
    if (k % 2 == 1)
      q += ((k - 1) / 2 % 2 == 0 ? 1.0 : -1.0) * a;  // Q: +a1 − a3 + a5
    else
      p += (k / 2 % 2 == 0 ? 1.0 : -1.0) * a;        // P: 1 − a2 + a4 − a6
  }
  const double chi = x - (0.5 * n + 0.25) * kPi;
  return std::sqrt(2.0 / (kPi * x)) * C(p, -q) * std::polar(1.0, -chi);
}

// A rough upper estimate of |H_n^(2)(x)|: the larger of its far value and Y_n's small-argument growth
// (n − 1)! (2/x)^n / π (in logarithms). Only decides how many terms to sum.
double log_hankel_bound(int n, double x) {
  const double far = 0.5 * std::log(2.0 / (kPi * x));
  if (n == 0) return std::max(far, std::log(std::max(1.0, std::abs(std::log(x)))));
  return std::max(far, std::lgamma(static_cast<double>(n)) + n * std::log(2.0 / x) - std::log(kPi));
}

}  // namespace

std::complex<double> hankel2_zero_far(double x) {
  return std::sqrt(2.0 / (kPi * x)) * std::polar(1.0, -(x - 0.25 * kPi));
}

void hankel2_orders(double x, int count, std::complex<double>* out) {
  if (count <= 0) return;
  if (x >= std::max(30.0, 2.0 * count * count)) {
    for (int n = 0; n < count; ++n) out[n] = hankel2_expansion(n, x);
    return;
  }
  // Y_n by upward recurrence from Y_0, Y_1 (stable upwards); J_n from the library (upward recurrence is not
  // stable for n > x).
  double y_prev = std::cyl_neumann(0.0, x), y = std::cyl_neumann(1.0, x);
  out[0] = C(std::cyl_bessel_j(0.0, x), -y_prev);
  if (count > 1) out[1] = C(std::cyl_bessel_j(1.0, x), -y);
  for (int n = 2; n < count; ++n) {
    const double y_next = (2.0 * (n - 1) / x) * y - y_prev;
    y_prev = y;
    y = y_next;
    out[n] = C(std::cyl_bessel_j(static_cast<double>(n), x), -y);
  }
}

CylinderCoefficients cylinder_coefficients(double ka) {
  if (!(ka > 0.0) || ka > kCylinderMaxKa)
    throw std::invalid_argument("cylinder_coefficients: ka must be in (0, " + std::to_string(kCylinderMaxKa) + "]");
  CylinderCoefficients c;
  c.ka = ka;
  // J_n, H_n for n = 0 … kCylinderMaxTerms (one more than kept: the derivatives need n + 1).
  std::array<double, kCylinderMaxTerms + 1> j{};
  std::array<C, kCylinderMaxTerms + 1> h{};
  hankel2_orders(ka, kCylinderMaxTerms + 1, h.data());
  for (int n = 0; n <= kCylinderMaxTerms; ++n) j[n] = h[n].real();
  c.terms = kCylinderMaxTerms;
  for (int n = 0; n < kCylinderMaxTerms; ++n) {
    c.soft[n] = -j[n] / h[n];
    // Z'_n = (Z_{n−1} − Z_{n+1}) / 2, Z'_0 = −Z_1.
    const double jd = n == 0 ? -j[1] : 0.5 * (j[n - 1] - j[n + 1]);
    const C hd = n == 0 ? -h[1] : 0.5 * (h[n - 1] - h[n + 1]);
    c.hard[n] = -jd / hd;
    // Kept until they underflow: with both ends near the cylinder the terms c_n H_n(kρ') H_n(kρ) fall only as
    // (a²/ρρ')^n, however small c_n is.
    if (n >= 2 && std::abs(c.soft[n]) < 1e-280 && std::abs(c.hard[n]) < 1e-280) {
      c.terms = n + 1;
      break;
    }
  }
  return c;
}

std::complex<double> cylinder_scattered(const CylinderCoefficients& c, CylinderPolarization polarization,
                                        double k_rho_source, double k_rho_observer, double delta_phi_rad) {
  const double xs = std::max(k_rho_source, c.ka), xo = std::max(k_rho_observer, c.ka);
  const auto& cn = polarization == CylinderPolarization::kSoft ? c.soft : c.hard;
  // Terms to sum: until the n-th term's estimate is below 1e-14 of the first's (the terms fall geometrically).
  const double log_first = std::log(std::max(std::abs(cn[0]), std::abs(cn[1])) + 1e-300) +
                           log_hankel_bound(0, xs) + log_hankel_bound(0, xo);
  int count = 2;
  while (count < c.terms &&
         std::log(std::abs(cn[count]) + 1e-300) + log_hankel_bound(count, xs) + log_hankel_bound(count, xo) >
             log_first - 32.2)  // e^−32.2 ≈ 1e-14
    ++count;
  std::array<C, kCylinderMaxTerms> hs, ho;
  hankel2_orders(xs, count, hs.data());
  hankel2_orders(xo, count, ho.data());
  C sum = cn[0] * hs[0] * ho[0];
  for (int n = 1; n < count; ++n) sum += 2.0 * std::cos(n * delta_phi_rad) * cn[n] * hs[n] * ho[n];
  return sum;
}

}  // namespace rfidray
