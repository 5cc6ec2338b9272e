#include "core/dielectric_half_space.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "core/error.h"
#include "core/gauss_legendre.h"
#include "core/units.h"

namespace rfidray {
namespace {

using C = std::complex<double>;

// e^{−36}: the integrands' factor e^{−s h} at the end of the [k₀, ∞) part, below double precision of the image.
constexpr double kDecayExponent = 36.0;
// The table's grid: ρ_i = c·(e^{iδ} − 1), c = h/2, δ ≤ 0.04 (4-point interpolation error ~δ⁴ ≈ 3e−6).
constexpr double kGridDelta = 0.04;

// k_z in the lower medium, the root with Im ≤ 0 (waves decaying away from the surface).
C lower_kz(C eps_k0_sq, double k_rho) {
  C w = std::sqrt(eps_k0_sq - k_rho * k_rho);
  if (w.imag() > 0.0) w = -w;
  return w;
}

struct Coefficients {
  C te;            // R_TE
  C phi_remainder; // R_φ − R_φ(∞)
};

Coefficients coefficients(double k_rho, C kz0, C eps, double k0, C r_phi_inf) {
  const C kz1 = lower_kz(eps * (k0 * k0), k_rho);
  const C r_te = (kz0 - kz1) / (kz0 + kz1);
  const C r_tm = (eps * kz0 - kz1) / (eps * kz0 + kz1);
  const C r_phi = r_te + (kz0 * kz0 / (k_rho * k_rho)) * (r_te + r_tm);
  return {r_te, r_phi - r_phi_inf};
}

// The two Sommerfeld integrals at ρ (vector: all of it; scalar: without its quasi-static image).
HalfSpaceKernelValue integrate(double rho, double h, double k0, C eps, C r_phi_inf) {
  const auto& g = gauss_legendre<16>();
  C sum_a = 0.0, sum_p = 0.0;
  // [0, k₀]: k_ρ = k₀ sin θ, k_z = k₀ cos θ, k_ρ/(jk_z) dk_ρ = −j k₀ sin θ dθ.
  for (int panel = 0; panel < 2; ++panel) {
    const double t0 = panel * 0.25 * kPi, half = 0.125 * kPi;
    for (int i = 0; i < 16; ++i) {
      const double theta = t0 + half * (1.0 + g.x[i]);
      const double k_rho = k0 * std::sin(theta), kz0 = k0 * std::cos(theta);
      const Coefficients c = coefficients(k_rho, C(kz0, 0.0), eps, k0, r_phi_inf);
      const C f = std::cyl_bessel_j(0.0, k_rho * rho) * std::polar(1.0, -kz0 * h) * C(0.0, -k0 * std::sin(theta)) *
                  (g.w[i] * half);
      sum_a += c.te * f;
      sum_p += c.phi_remainder * f;
    }
  }
  // [k₀, ∞): k_ρ = √(k₀² + s²), k_z = −js, k_ρ/(jk_z) dk_ρ = ds.
  const double s_max = kDecayExponent / h;
  const double s_branch = eps.real() > 1.0 ? k0 * std::sqrt(eps.real() - 1.0) : 0.0;
  const double width = std::min(4.0 / h, kTwoPi / std::max(rho, 1e-12));
  std::vector<double> edges{0.0};
  if (s_branch > 0.0 && s_branch < s_max) edges.push_back(s_branch);
  edges.push_back(s_max);
  for (size_t e = 0; e + 1 < edges.size(); ++e) {
    const int panels = std::max(1, static_cast<int>(std::ceil((edges[e + 1] - edges[e]) / width)));
    const double step = (edges[e + 1] - edges[e]) / panels;
    for (int p = 0; p < panels; ++p) {
      const double lo = edges[e] + p * step, half = 0.5 * step;
      for (int i = 0; i < 16; ++i) {
        const double s = lo + half * (1.0 + g.x[i]);
        const double k_rho = std::sqrt(k0 * k0 + s * s);
        const Coefficients c = coefficients(k_rho, C(0.0, -s), eps, k0, r_phi_inf);
        const double f = std::cyl_bessel_j(0.0, k_rho * rho) * std::exp(-s * h) * (g.w[i] * half);
        sum_a += c.te * f;
        sum_p += c.phi_remainder * f;
      }
    }
  }
  return {sum_a / (4.0 * kPi), sum_p / (4.0 * kPi)};
}

C quasi_static_image(C eps) { return -(eps - 1.0) / (eps + 1.0); }

void check(double distance_m, double frequency_hz, C eps) {
  if (!(std::isfinite(distance_m) && distance_m > 0.0))
    throw InputError("dielectric half-space: the distance must be a finite number > 0 (m)");
  if (!(std::isfinite(frequency_hz) && frequency_hz > 0.0))
    throw InputError("dielectric half-space: the frequency must be a finite number > 0 (Hz)");
  if (!(std::isfinite(eps.real()) && std::isfinite(eps.imag()) && eps.real() >= 1.0 && eps.imag() <= 0.0))
    throw InputError("dielectric half-space: the relative permittivity must have Re ≥ 1 and Im ≤ 0 (ε' − jσ/ωε0)");
}

class DielectricHalfSpace final : public WireSurroundKernel {
 public:
  DielectricHalfSpace(double distance_m, double frequency_hz, C eps, double max_separation_m)
      : h_(2.0 * distance_m), k_(wavenumber_rad_m(frequency_hz)), r_phi_inf_(quasi_static_image(eps)) {
    c_ = 0.5 * h_;
    rho_max_ = 1.05 * max_separation_m + 1e-6;
    const double span = std::log1p(rho_max_ / c_);
    const int n = std::max(8, static_cast<int>(std::ceil(span / kGridDelta)));
    delta_ = span / n;
    vector_.resize(n + 1);
    scalar_.resize(n + 1);
    for (int i = 0; i <= n; ++i) {
      const HalfSpaceKernelValue v = integrate(c_ * std::expm1(i * delta_), h_, k_, eps, r_phi_inf_);
      vector_[i] = v.vector;
      scalar_[i] = v.scalar;
    }
  }

  C vector_integral(double a1, double a2, double b1, double b2) const override {
    return rectangle(vector_, a1, a2, b1, b2);
  }
  C scalar_integral(double a1, double a2, double b1, double b2) const override {
    return r_phi_inf_ * line_kernel_integral(a1, a2, b1, b2, h_, k_) + rectangle(scalar_, a1, a2, b1, b2);
  }

 private:
  // 4-point Lagrange interpolation in the grid's index u = ln(1 + ρ/c)/δ.
  C interpolate(const std::vector<C>& table, double rho) const {
    if (rho > rho_max_) throw std::logic_error("dielectric half-space: separation beyond the kernel's table");
    const double u = std::log1p(rho / c_) / delta_;
    const int last = static_cast<int>(table.size()) - 1;
    const int i0 = std::clamp(static_cast<int>(std::floor(u)) - 1, 0, last - 3);
    C sum = 0.0;
    for (int i = i0; i < i0 + 4; ++i) {
      double w = 1.0;
      for (int j = i0; j < i0 + 4; ++j)
        if (j != i) w *= (u - j) / static_cast<double>(i - j);
      sum += w * table[i];
    }
    return sum;
  }
  C rectangle(const std::vector<C>& table, double a1, double a2, double b1, double b2) const {
    const auto& g = gauss_legendre<6>();
    C sum = 0.0;
    for (int i = 0; i < 6; ++i) {
      const double za = 0.5 * (a1 + a2) + 0.5 * (a2 - a1) * g.x[i];
      for (int j = 0; j < 6; ++j) {
        const double zb = 0.5 * (b1 + b2) + 0.5 * (b2 - b1) * g.x[j];
        sum += g.w[i] * g.w[j] * interpolate(table, std::abs(za - zb));
      }
    }
    return 0.25 * (a2 - a1) * (b2 - b1) * sum;
  }

  double h_, k_;
  C r_phi_inf_;
  double c_ = 0.0, delta_ = 0.0, rho_max_ = 0.0;
  std::vector<C> vector_, scalar_;
};

}  // namespace

std::unique_ptr<WireSurroundKernel> dielectric_half_space(double distance_m, double frequency_hz, C relative_permittivity,
                                                          double max_separation_m) {
  check(distance_m, frequency_hz, relative_permittivity);
  if (!(std::isfinite(max_separation_m) && max_separation_m > 0.0))
    throw InputError("dielectric half-space: the largest separation must be a finite number > 0 (m)");
  return std::make_unique<DielectricHalfSpace>(distance_m, frequency_hz, relative_permittivity, max_separation_m);
}

HalfSpaceKernelValue half_space_reflected_kernel(double rho_m, double distance_m, double frequency_hz,
                                                 C relative_permittivity) {
  check(distance_m, frequency_hz, relative_permittivity);
  const double h = 2.0 * distance_m, k = wavenumber_rad_m(frequency_hz);
  const C r_inf = quasi_static_image(relative_permittivity);
  HalfSpaceKernelValue v = integrate(rho_m, h, k, relative_permittivity, r_inf);
  const double r = std::hypot(rho_m, h);
  v.scalar += r_inf * std::polar(1.0, -k * r) / (4.0 * kPi * r);
  return v;
}

}  // namespace rfidray
