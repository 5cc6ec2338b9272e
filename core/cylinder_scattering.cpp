#include "core/cylinder_scattering.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/units.h"

namespace rfidray {
namespace {

using C = std::complex<double>;

// Hankel's expansion of H_n^(2)(x), A&S 9.2.5–9.2.10: √(2/πx) (P − jQ) e^{−jχ}, χ = x − (n/2 + 1/4)π,
// (k ≤ 7), P = Σ_{k even} (−1)^{k/2} a_k, Q = Σ_{k odd} (−1)^{(k−1)/2} a_k, a_k = Π_{m=1}^{k} (4n² − (2m − 1)²) / (k! (8x)^k).
// `zero_phase` is √(2/πx) e^{−j(x − π/4)}, the same for every order: e^{−jχ} is it times j^n, an exact quarter turn
// (one sine and cosine per x instead of one per order; the orders' arguments x − nπ/2 also lose no bits to rounding).
C hankel2_expansion(int n, double x, C zero_phase) {
  const double mu = 4.0 * n * n;
  double a = 1.0, p = 1.0, q = 0.0;
  for (int k = 1; k <= 7; ++k) {
    a *= (mu - (2.0 * k - 1.0) * (2.0 * k - 1.0)) / (k * 8.0 * x);
    if (k % 2 == 1)
      q += ((k - 1) / 2 % 2 == 0 ? 1.0 : -1.0) * a;  // Q: a1 − a3 + a5 − a7
    else
      p += (k / 2 % 2 == 0 ? 1.0 : -1.0) * a;        // P: 1 − a2 + a4 − a6
  }
  C turned = zero_phase;  // × j^n
  switch (n % 4) {
    case 1: turned = C(-zero_phase.imag(), zero_phase.real()); break;
    case 2: turned = -zero_phase; break;
    case 3: turned = C(zero_phase.imag(), -zero_phase.real()); break;
    default: break;
  }
  return C(p, -q) * turned;
}

// Y_0 and Y_1 from the J_n of one Miller ladder (A&S 9.1.88, and its derivative for Y_1 = −Y_0′ with
// J_0′ = −J_1, J_{2k}′ = (J_{2k−1} − J_{2k+1})/2):
//   Y_0 = (2/π)(ln(x/2) + γ) J_0 − (4/π) Σ_{k≥1} (−1)^k J_{2k}/k,
//   Y_1 = (2/π)((ln(x/2) + γ) J_1 − J_0/x) + (2/π) Σ_{k≥1} (−1)^k (J_{2k−1} − J_{2k+1})/k.
// No division by J_0 (the Wronskian would need one) and no cancellation worse than ln(x): within ~1e-15 of the
// library's Y_0, Y_1 for x ≤ 300 (2e-15 absolute; tests/core/test_cylinder_scattering.cpp), at a fraction of their cost — the
// library's Y_n were 14 % of `full`'s CPU on the paper warehouse (thin posts).
constexpr double kNeumannSeriesMaxX = 300.0;
// Terms k: J_{2k}(x) is below 1e-17 of the largest once 2k exceeds x by 30 + 4·x^{1/3} (core/wedge_series.cpp).
int neumann_series_terms(double x) { return static_cast<int>((x + 30.0 + 4.0 * std::cbrt(x)) / 2.0) + 1; }
// 4·x^{1/3} ≤ 27 for x ≤ 300.
constexpr int kNeumannSeriesOrders = 2 * (static_cast<int>((kNeumannSeriesMaxX + 30.0 + 27.0) / 2.0) + 1) + 2;
void neumann_y0_y1(double x, const double* j, int k_terms, double& y0, double& y1) {
  constexpr double kEulerGamma = 0.57721566490153286061;
  const double log_term = std::log(0.5 * x) + kEulerGamma;
  double sum0 = 0.0, sum1 = 0.0;
  for (int k = 1; k <= k_terms; ++k) {
    const double sign = k % 2 == 0 ? 1.0 : -1.0;
    sum0 += sign * j[2 * k] / k;
    sum1 += sign * (j[2 * k - 1] - j[2 * k + 1]) / k;
  }
  y0 = (2.0 / kPi) * log_term * j[0] - (4.0 / kPi) * sum0;
  y1 = (2.0 / kPi) * (log_term * j[1] - j[0] / x) + (2.0 / kPi) * sum1;
}

}  // namespace

void bessel_j_orders(double x, int count, double* out) {
  if (count <= 0) return;
  // Start well above both the highest order wanted and x (Numerical Recipes' bessj: +√(40 n)).
  const int top = std::max(count, static_cast<int>(x) + 1);
  const int m = 2 * ((top + 16 + static_cast<int>(std::sqrt(40.0 * top))) / 2);
  double j_above = 0.0, j = 1e-300, sum = 0.0;  // J_{k+1}, J_k up to a common factor
  for (int k = m; k >= 1; --k) {
    const double j_below = (2.0 * k / x) * j - j_above;  // J_{k−1}
    j_above = j;
    j = j_below;
    if (std::abs(j) > 1e250) {  // rescale everything kept so far
      j *= 1e-250;
      j_above *= 1e-250;
      sum *= 1e-250;
      for (int n = k; n < count; ++n) out[n] *= 1e-250;
    }
    if (k - 1 < count) out[k - 1] = j;
    if ((k - 1) % 2 == 0 && k - 1 > 0) sum += j;
  }
  const double norm = j + 2.0 * sum;  // J_0 + 2 Σ J_2k = 1
  for (int n = 0; n < count; ++n) out[n] /= norm;
}

std::complex<double> hankel2_zero_far(double x) {
  return std::sqrt(2.0 / (kPi * x)) * std::polar(1.0, -(x - 0.25 * kPi));
}

void hankel2_orders(double x, int count, std::complex<double>* out, int significant) {
  if (count <= 0) return;
  if (significant < 0) significant = count;
  if (x >= std::max(30.0, 2.0 * significant * significant)) {
    const C zero_phase = hankel2_zero_far(x);
    for (int n = 0; n < count; ++n) out[n] = hankel2_expansion(n, x, zero_phase);
    return;
  }
  // J_n for the orders wanted and, up to x ≤ kNeumannSeriesMaxX, for Neumann's series of Y_0 and Y_1 below.
  std::array<double, kNeumannSeriesOrders + kCylinderMaxTerms + 2> j;  // every order read is written first
  const bool series = x <= kNeumannSeriesMaxX;
  const int k_terms = series ? neumann_series_terms(x) : 0;
  bessel_j_orders(x, std::max(count, 2 * k_terms + 2), j.data());
  // Y_n upwards from Y_0, Y_1 (stable upwards).
  double y_prev = 0.0, y = 0.0;
  if (series) {
    neumann_y0_y1(x, j.data(), k_terms, y_prev, y);
  } else {
    y_prev = std::cyl_neumann(0.0, x);
    y = std::cyl_neumann(1.0, x);
  }
  out[0] = C(j[0], -y_prev);
  if (count > 1) out[1] = C(j[1], -y);
  for (int n = 2; n < count; ++n) {
    const double y_next = (2.0 * (n - 1) / x) * y - y_prev;
    y_prev = y;
    y = y_next;
    out[n] = C(j[n], -y);
  }
}

CylinderCoefficients cylinder_coefficients(double ka, int terms) {
  if (!(ka > 0.0) || ka > kCylinderMaxKa)
    throw std::invalid_argument("cylinder_coefficients: ka must be in (0, " + std::to_string(kCylinderMaxKa) + "]");
  CylinderCoefficients c;
  c.ka = ka;
  c.terms = std::clamp(terms, 2, kCylinderMaxTerms);
  // J_n, H_n for n = 0 … terms (one more than kept: the derivatives need n + 1).
  std::array<C, kCylinderMaxTerms + 1> h{};
  hankel2_orders(ka, c.terms + 1, h.data());
  for (int n = 0; n < c.terms; ++n) {
    // Z'_n = (Z_{n−1} − Z_{n+1}) / 2, Z'_0 = −Z_1.
    const C hd = n == 0 ? -h[1] : 0.5 * (h[n - 1] - h[n + 1]);
    if (!std::isfinite(std::abs(h[n + 1]))) {  // Y_n overflowed (a very thin wire): c_n underflowed long before
      c.terms = std::max(n, 2);
      break;
    }
    c.soft[n] = -h[n].real() / h[n];
    c.hard[n] = -hd.real() / hd;
  }
  return c;
}

int cylinder_terms(double ka, double k_rho_source, double k_rho_observer) {
  const double xs = std::max(k_rho_source, ka), xo = std::max(k_rho_observer, ka);
  // |c_n H_n(kρ') H_n(kρ)| from the small-argument forms |J_n(x)| ≈ (x/2)^n / n! and |H_n(x)| ≈ the larger of
  // √(2/πx) and (n − 1)! (2/x)^n / π (logarithms, accumulated over n): an estimate of the tail, where n > ka.
  const double log_half_ka = std::log(0.5 * ka), log_pi = std::log(kPi);
  const double log2_ka = std::log(2.0 / ka), log2_xs = std::log(2.0 / xs), log2_xo = std::log(2.0 / xo);
  const auto far = [](double x) { return 0.5 * std::log(2.0 / (kPi * x)); };
  const double far_ka = far(ka), far_xs = far(xs), far_xo = far(xo);
  double log_factorial = 0.0, log_gamma = 0.0;  // ln n!, ln (n − 1)!
  double first = -1e300;
  int n = 0;
  for (; n < kCylinderMaxTerms; ++n) {
    if (n >= 1) {
      log_factorial += std::log(static_cast<double>(n));
      if (n >= 2) log_gamma += std::log(static_cast<double>(n - 1));
    }
    const auto log_h = [&](double far_x, double log2_x) {
      return n == 0 ? far_x : std::max(far_x, log_gamma + n * log2_x - log_pi);
    };
    const double term = n * log_half_ka - log_factorial - log_h(far_ka, log2_ka) + log_h(far_xs, log2_xs) +
                        log_h(far_xo, log2_xo);
    if (n <= 1) {
      first = std::max(first, term);
      continue;
    }
    if (n >= ka + 2.0 && term < first - 36.8) break;  // e^−36.8 ≈ 1e-16
  }
  return std::min(n + 1, kCylinderMaxTerms);
}

CylinderField cylinder_scattered(const CylinderCoefficients& c, double k_rho_source, double k_rho_observer,
                                 double delta_phi_rad) {
  const double xs = std::max(k_rho_source, c.ka), xo = std::max(k_rho_observer, c.ka);
  // Orders whose c_n is above 1e-12 of the largest: far from the cylinder (H_n of about equal size for every n
  // below √x) the others add less than that; for them Hankel's expansion may be inexact.
  double largest = 0.0;
  for (int n = 0; n < c.terms; ++n) largest = std::max({largest, std::abs(c.soft[n]), std::abs(c.hard[n])});
  int significant = c.terms;
  while (significant > 1 && std::max(std::abs(c.soft[significant - 1]), std::abs(c.hard[significant - 1])) <
                                1e-12 * largest)
    --significant;
  std::array<C, kCylinderMaxTerms> hs, ho;
  hankel2_orders(xs, c.terms, hs.data(), significant);
  hankel2_orders(xo, c.terms, ho.data(), significant);
  CylinderField out{c.soft[0] * hs[0] * ho[0], c.hard[0] * hs[0] * ho[0]};
  // cos nΔφ by Chebyshev's recurrence cos nθ = 2 cos θ cos (n−1)θ − cos (n−2)θ: one cosine per link instead of
  // one per order. Its rounding error is at most ~n²/2 ulps (the recurrence carries it by U_{n−k}, |U_m| ≤ m + 1):
  // below 3e-13 at the 48th order, far below the series' own truncation (1e-10 at worst, the header).
  const double cos1 = std::cos(delta_phi_rad);
  double cos_prev = 1.0, cos_n = cos1;
  for (int n = 1; n < c.terms; ++n) {
    const C h = 2.0 * cos_n * hs[n] * ho[n];
    out.soft += c.soft[n] * h;
    out.hard += c.hard[n] * h;
    const double cos_next = 2.0 * cos1 * cos_n - cos_prev;
    cos_prev = cos_n;
    cos_n = cos_next;
  }
  return out;
}

CylinderScatteringBound::CylinderScatteringBound(double ka_max) {
  const CylinderCoefficients c = cylinder_coefficients(ka_max);  // throws outside (0, kCylinderMaxKa]
  std::array<C, kCylinderMaxTerms> h{};
  hankel2_orders(kCylinderBoundMinX, kCylinderMaxTerms, h.data());
  // Where |c_n| is known to grow with ka (the header): the first zeros of Y_0 and Y_1 (A&S table 9.5), as lower bounds.
  constexpr double kY0FirstZero = 0.8935, kY1FirstZero = 2.1971;
  double soft = 0.0, hard = 0.0;
  for (int n = 0; n < kCylinderMaxTerms; ++n) {
    const double m_n = n == 0 ? 2.0 / kPi : kCylinderBoundMinX * std::norm(h[n]);
    if (!std::isfinite(m_n)) break;  // past where Y_n overflows: c_n underflowed long before
    const double soft_limit = n == 0 ? kY0FirstZero : std::max(kY1FirstZero, static_cast<double>(n));
    const double hard_limit = n == 0 ? kY1FirstZero : static_cast<double>(n);
    const double c_soft = n >= c.terms ? 1.0 : ka_max < soft_limit ? std::abs(c.soft[n]) : 1.0;
    const double c_hard = n >= c.terms ? 1.0 : ka_max < hard_limit ? std::abs(c.hard[n]) : 1.0;
    const double weight = (n == 0 ? 1.0 : 2.0) * m_n;
    soft += weight * c_soft;
    hard += weight * c_hard;
  }
  soft_sum_ = soft;
  hard_sum_ = hard;
}

CylinderBoundRatios CylinderScatteringBound::ratio(double k_rho_source, double k_rho_observer) const {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  if (!(k_rho_source >= kCylinderBoundMinX && k_rho_observer >= kCylinderBoundMinX)) return {kInf, kInf};
  // Σ ε_n C_n M_n / √(xs xo) over √(2/(π (xs + xo))); 1 % for the rounding of the series and its Hankel expansion.
  const double scale =
      1.01 * std::sqrt(0.5 * kPi * (k_rho_source + k_rho_observer) / (k_rho_source * k_rho_observer));
  return {soft_sum_ * scale, hard_sum_ * scale};
}

std::complex<double> cylinder_scattered(const CylinderCoefficients& c, CylinderPolarization polarization,
                                        double k_rho_source, double k_rho_observer, double delta_phi_rad) {
  const CylinderField f = cylinder_scattered(c, k_rho_source, k_rho_observer, delta_phi_rad);
  return polarization == CylinderPolarization::kSoft ? f.soft : f.hard;
}

}  // namespace rfidray
