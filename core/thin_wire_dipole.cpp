#include "core/thin_wire_dipole.h"

#include <Eigen/Dense>
#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/gauss_legendre.h"
#include "core/units.h"

namespace rfidray {
namespace {

constexpr double kMu0_H_m = 1.25663706212e-6;

const GaussLegendre<6>& gauss6() { return gauss_legendre<6>(); }
const GaussLegendre<24>& gauss24() { return gauss_legendre<24>(); }

// ∫∫ dz dz' / √((z − z')² + ρ²) over [a1, a2] × [b1, b2], from the antiderivative F(u) = u·asinh(u/ρ) − √(u² + ρ²).
double static_double_integral(double a1, double a2, double b1, double b2, double rho) {
  const auto F = [rho](double u) { return u * std::asinh(u / rho) - std::sqrt(u * u + rho * rho); };
  return -(F(a2 - b2) - F(a2 - b1) - F(a1 - b2) + F(a1 - b1));
}

// ∫∫ (e^{−jkR} − 1)/R over the rectangle, R = √((z − z')² + b²): smooth (→ −jk as R → 0), 6 × 6 points.
std::complex<double> smooth_double_integral(double a1, double a2, double b1, double b2, double b, double k) {
  const auto& g = gauss6();
  std::complex<double> sum = 0.0;
  for (int i = 0; i < 6; ++i) {
    const double za = 0.5 * (a1 + a2) + 0.5 * (a2 - a1) * g.x[i];
    for (int j = 0; j < 6; ++j) {
      const double zb = 0.5 * (b1 + b2) + 0.5 * (b2 - b1) * g.x[j];
      const double R = std::sqrt((za - zb) * (za - zb) + b * b);
      const double kr = k * R;
      // (e^{−jkR} − 1)/R without cancellation for small kR: −2j·sin(kR/2)·e^{−jkR/2}/R.
      const std::complex<double> v =
          std::complex<double>(0.0, -2.0) * std::sin(0.5 * kr) * std::polar(1.0, -0.5 * kr) / R;
      sum += g.w[i] * g.w[j] * v;
    }
  }
  return 0.25 * (a2 - a1) * (b2 - b1) * sum;
}

// The wire's own kernel, exact: the source current spread around the surface (radius a), observed on the
// surface; ρ = 2a·sin(φ/2) is the chord to the source point. φ = π t² takes the log singularity at φ = 0 out.
std::complex<double> wire_double_integral(double a1, double a2, double b1, double b2, double a, double k) {
  const auto& g = gauss24();
  double avg = 0.0;
  for (int i = 0; i < 24; ++i) {
    const double t = 0.5 * (g.x[i] + 1.0);
    const double phi = kPi * t * t;
    const double dphi_dt = 2.0 * kPi * t;
    const double rho = 2.0 * a * std::sin(0.5 * phi);
    avg += 0.5 * g.w[i] * dphi_dt * static_double_integral(a1, a2, b1, b2, rho);
  }
  avg /= kPi;
  return (avg + smooth_double_integral(a1, a2, b1, b2, a, k)) / (4.0 * kPi);
}

class PerfectConductorPlane final : public WireSurroundKernel {
 public:
  PerfectConductorPlane(double distance_m, double k) : separation_m_(2.0 * distance_m), k_(k) {}
  std::complex<double> vector_integral(double a1, double a2, double b1, double b2) const override {
    return -line_kernel_integral(a1, a2, b1, b2, separation_m_, k_);
  }
  std::complex<double> scalar_integral(double a1, double a2, double b1, double b2) const override {
    return -line_kernel_integral(a1, a2, b1, b2, separation_m_, k_);
  }

 private:
  double separation_m_, k_;
};

void check_positive(double v, const char* field, const char* unit) {
  if (!(std::isfinite(v) && v > 0.0))
    throw InputError(std::string("thin-wire dipole: ") + field + " must be a finite number > 0 " + unit);
}

}  // namespace

std::complex<double> line_kernel_integral(double a1, double a2, double b1, double b2, double b_m, double k_rad_m) {
  return (static_double_integral(a1, a2, b1, b2, b_m) + smooth_double_integral(a1, a2, b1, b2, b_m, k_rad_m)) /
         (4.0 * kPi);
}

std::unique_ptr<WireSurroundKernel> perfect_conductor_plane(double distance_m, double frequency_hz) {
  check_positive(distance_m, "the distance to the plane", "(m)");
  check_positive(frequency_hz, "the frequency", "(Hz)");
  return std::make_unique<PerfectConductorPlane>(distance_m, wavenumber_rad_m(frequency_hz));
}

int default_dipole_segments(const ThinWireDipole& dipole) {
  const double n = dipole.length_m / (1.5 * dipole.radius_m);
  int segments = static_cast<int>(std::lround(n / 2.0)) * 2;
  if (!(segments >= 40)) segments = 40;  // also NaN
  if (segments > 400) segments = 400;
  return segments;
}

std::complex<double> dipole_input_impedance(const ThinWireDipole& dipole, double frequency_hz,
                                            const WireSurroundKernel* surround, int segments) {
  check_positive(dipole.length_m, "length_m", "(m)");
  check_positive(dipole.radius_m, "radius_m", "(m)");
  check_positive(frequency_hz, "frequency", "(Hz)");
  if (!(std::isfinite(dipole.conductivity_s_m) && dipole.conductivity_s_m >= 0.0))
    throw InputError("thin-wire dipole: conductivity_s_m must be finite and ≥ 0 (0: a perfect conductor)");
  if (!(dipole.radius_m < 0.1 * dipole.length_m))
    throw InputError("thin-wire dipole: radius_m must be below a tenth of length_m (a thin wire)");
  if (segments == 0) segments = default_dipole_segments(dipole);
  if (segments < 4 || segments % 2 != 0 || segments > 4000)
    throw InputError("thin-wire dipole: segments must be even, from 4 to 4000 (got " + std::to_string(segments) + ")");

  const double k = wavenumber_rad_m(frequency_hz);
  const double omega = kTwoPi * frequency_hz;
  const double a = dipole.radius_m;
  const double D = dipole.length_m / segments;
  const int M = segments - 1;  // inner nodes: unknown currents

  // Toeplitz: the entry of test node m and basis node n depends on q = m − n only (and is even in q).
  const std::complex<double> jw_mu(0.0, omega * kMu0_H_m);
  const std::complex<double> inv_jw_eps_d2 = 1.0 / std::complex<double>(0.0, omega * kVacuumPermittivity_F_m * D * D);
  const auto potential = [&](double a1, double a2, double b1, double b2, bool vector) {
    std::complex<double> v = wire_double_integral(a1, a2, b1, b2, a, k);
    if (surround) v += vector ? surround->vector_integral(a1, a2, b1, b2) : surround->scalar_integral(a1, a2, b1, b2);
    return v;
  };
  std::vector<std::complex<double>> entry(M);
  for (int q = 0; q < M; ++q) {
    const double c = q * D;
    // Vector potential: the test pulse around node m against the basis pulse around node n.
    const std::complex<double> A = potential(c - 0.5 * D, c + 0.5 * D, -0.5 * D, 0.5 * D, true);
    // Scalar potential: a triangle's derivative is +1/Δ on the segment below its node and −1/Δ above.
    const std::complex<double> P = potential(c, c + D, 0.0, D, false) - potential(c, c + D, -D, 0.0, false) -
                                   potential(c - D, c, 0.0, D, false) + potential(c - D, c, -D, 0.0, false);
    entry[q] = jw_mu * A + inv_jw_eps_d2 * P;
  }
  if (dipole.conductivity_s_m > 0.0) {
    // Skin-effect loss per metre, Z_s / (2πa), tested and expanded on the triangles: ∫T_m T_n = 2Δ/3, Δ/6.
    const double r_s = std::sqrt(omega * kMu0_H_m / (2.0 * dipole.conductivity_s_m));
    const std::complex<double> z_per_m = std::complex<double>(r_s, r_s) / (kTwoPi * a);
    entry[0] += z_per_m * (2.0 * D / 3.0);
    if (M > 1) entry[1] += z_per_m * (D / 6.0);
  }

  // Symmetric currents I_i = I_{M−1−i}: unknowns 0..c, c the centre node (the feed).
  const int centre = (M - 1) / 2;
  const int n_half = centre + 1;
  Eigen::MatrixXcd Z(n_half, n_half);
  for (int m = 0; m < n_half; ++m)
    for (int j = 0; j < n_half; ++j) {
      std::complex<double> z = entry[std::abs(m - j)];
      if (j != centre) z += entry[std::abs(m - (M - 1 - j))];
      Z(m, j) = z;
    }
  Eigen::VectorXcd V = Eigen::VectorXcd::Zero(n_half);
  V(centre) = 1.0;
  const Eigen::VectorXcd I = Z.partialPivLu().solve(V);
  const std::complex<double> z_in = 1.0 / I(centre);
  if (!(std::isfinite(z_in.real()) && std::isfinite(z_in.imag())))
    throw InputError("thin-wire dipole: the moment-method solve gave no finite impedance");
  return z_in;
}

}  // namespace rfidray
