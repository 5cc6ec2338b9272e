#pragma once
// Gauss–Legendre quadrature: N nodes and weights on (−1, 1), exact for polynomials of degree 2N − 1.
// Nodes by Newton's method on P_N (Golub–Welsch would need an eigen-solve). Thread-safe: gauss_legendre<N>()
// returns a function-local static, built once.
#include <array>
#include <cmath>

namespace rfidray {

template <int N>
struct GaussLegendre {
  std::array<double, N> x{}, w{};
  GaussLegendre() {
    constexpr double kPi_ = 3.14159265358979323846;
    for (int i = 0; i < N; ++i) {
      double z = std::cos(kPi_ * (i + 0.75) / (N + 0.5)), dp = 0.0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1.0, p1 = z;
        for (int n = 2; n <= N; ++n) {
          const double p2 = ((2.0 * n - 1.0) * z * p1 - (n - 1.0) * p0) / n;
          p0 = p1;
          p1 = p2;
        }
        dp = N * (z * p1 - p0) / (z * z - 1.0);
        const double dz = p1 / dp;
        z -= dz;
        if (std::abs(dz) < 1e-15) break;
      }
      x[i] = z;
      w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
  }
};

template <int N>
const GaussLegendre<N>& gauss_legendre() {
  static const GaussLegendre<N> g;
  return g;
}

}  // namespace rfidray
