#include "core/utd.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/units.h"

namespace rfidray {
namespace {

using C = std::complex<double>;

const C kEjPi4 = std::polar(1.0, kPi / 4.0);    // e^{jπ/4}
const C kEmjPi4 = std::polar(1.0, -kPi / 4.0);  // e^{−jπ/4}
const double kSqrtPi = std::sqrt(kPi);

// ∫_0^a e^{−jτ²} dτ = Σ_n (−j)^n a^{2n+1} / (n! (2n+1))  (the Fresnel integrals' power series, A&S 7.3.11–12,
// as one complex series). Used for a < 2, where its terms stay below ~10 and cancel to ~1e-15.
C fresnel_head(double a) {
  C power = a, sum = 0.0;
  for (int n = 0; n < 200; ++n) {
    const C term = power / double(2 * n + 1);
    sum += term;
    if (n > 3 && std::abs(term) < 1e-17 * std::abs(sum)) break;
    power *= C(0.0, -1.0) * a * a / double(n + 1);
  }
  return sum;
}

// e^{z²} erfc(z) for Re z > 0 by Laplace's continued fraction (A&S 7.1.14)
//   √π e^{z²} erfc(z) = 1/(z + (1/2)/(z + 1/(z + (3/2)/(z + 2/(z + …))))),
// evaluated backwards from a depth that falls with |z|: on arg z = π/4 the depth below is what a depth-600
// evaluation needs for 2e-15 relative at the interval's smaller |z| (80 at |z| = 2, 37 at 3, 22 at 4, 16 at 5,
// 13 at 6, 11 at 7, 10 at 8, 8 at 10, 7 at 14), plus one; checked over 2 ≤ |z| ≤ 10⁴ (max 1.9e-15), and the
// depth-600 value against an arbitrary-precision erfc. It was the hot loop of level `full` (a third of its time:
// bench/results/levels/README.md) and still serves X ≥ 64 directly, so each level's division is written out in reals
// (k ← z + (m/2)·k̄/|k|²) instead of std::complex's, which guards against overflow that |k| ≥ |z| ≥ 2 cannot reach.
C scaled_erfc(C z) {
  const double r = std::abs(z);
  const int depth = r < 3.0    ? 80
                    : r < 4.0  ? 40
                    : r < 5.0  ? 24
                    : r < 6.0  ? 17
                    : r < 7.0  ? 14
                    : r < 8.0  ? 12
                    : r < 10.0 ? 11
                    : r < 14.0 ? 9
                               : 8;
  double kr = z.real(), ki = z.imag();
  for (int m = depth; m >= 1; --m) {
    const double scale = 0.5 * m / (kr * kr + ki * ki);
    const double next_r = z.real() + scale * kr, next_i = z.imag() - scale * ki;
    kr = next_r;
    ki = next_i;
  }
  const double scale = 1.0 / (kSqrtPi * (kr * kr + ki * ki));
  return {scale * kr, -scale * ki};
}

// S(a) = e^{ja²}·∫_a^∞ e^{−jτ²} dτ, evaluated directly: the power series below a = 2, the continued fraction above.
C scaled_tail_direct(double a) {
  if (a < 2.0) return std::polar(1.0, a * a) * (0.5 * kSqrtPi * kEmjPi4 - fresnel_head(a));
  // ∫_a^∞ e^{−jτ²} dτ = e^{−jπ/4} (√π/2) erfc(e^{jπ/4} a) and erfc(z) = e^{−z²}·scaled, e^{−z²} = e^{−jX}.
  return kEmjPi4 * (0.5 * kSqrtPi) * scaled_erfc(kEjPi4 * a);
}

// Below a = 8 (X = 64) the direct evaluation is slow (up to ~80 terms or levels: 0.55 µs at X = 5, 0.13 µs at
// X = 30, gcc -O3) and `full` calls it four times per edge and link. There S is a Taylor series about the nearest
// of 161 nodes a_i = i/20, whose values are computed once by the direct evaluation: S satisfies S' = 2jaS − 1, so
// S'' = 2jS + 2jaS' and S^(m+1) = 2ja·S^(m) + 2jm·S^(m−1) (m ≥ 1). With |a − a_i| ≤ 1/40 and |2a| ≤ 16 the m-th
// term is of order 0.4^m/m! of S (1e-17 by m = 19); the series stops once a term is below 1e-17 of the sum
// (32–47 ns per call from X = 0.5 to 60, gcc -O3, one core).
constexpr double kTaylorStep = 0.05;
constexpr int kTaylorNodes = 161;  // a_i = 0 … 8
const std::array<C, kTaylorNodes>& taylor_nodes() {
  static const std::array<C, kTaylorNodes> nodes = [] {
    std::array<C, kTaylorNodes> n{};
    for (int i = 0; i < kTaylorNodes; ++i) n[i] = scaled_tail_direct(kTaylorStep * i);
    return n;
  }();
  return nodes;
}

// e^{jX}·∫_√X^∞ e^{−jτ²} dτ, the factor of F without the 2j√X (no overflow or cancellation for large X).
C scaled_tail(double x) {
  const double a = std::sqrt(std::max(x, 0.0));
  if (a >= 8.0) return scaled_tail_direct(a);
  const int i = static_cast<int>(std::lround(a / kTaylorStep));
  const double a0 = kTaylorStep * i, delta = a - a0;
  const C two_j_a(0.0, 2.0 * a0);
  C previous = taylor_nodes()[i];            // S^(m−1)
  C current = two_j_a * previous - 1.0;      // S^(m), m = 1
  C sum = previous + current * delta;
  double power = delta;                      // δ^m / m!
  for (int m = 1; m < 40; ++m) {
    const C next = two_j_a * current + C(0.0, 2.0 * m) * previous;
    power *= delta / double(m + 1);
    const C term = next * power;
    sum += term;
    if (std::abs(term.real()) + std::abs(term.imag()) < 1e-17 * (std::abs(sum.real()) + std::abs(sum.imag()))) break;
    previous = current;
    current = next;
  }
  return sum;
}

// cot(u)·F(kL·a) for one of the four terms. δ = 2n(u − mπ) is the observer's angle from the term's boundary,
// > 0 on the side where the boundary's geometrical-optics field exists (for each term's pole in 0 ≤ φ, φ' ≤ nπ:
// φ < φ' + π, φ > φ' − π, φ < π − φ', φ > (2n − 1)π − φ'). `side` (±1, 0: the angles' own) is the side to take
// within `band` of the boundary. On the pole: the limit n·√(2πkL)·e^{jπ/4}·side (KP eq. 29, leading term).
// Off it, on the other side than the angles': the term minus twice its jumping part
// J = cot(u)·j√(πX)·e^{jX}·e^{−jπ/4} (from F(X) = 2j√X e^{jX}(√π e^{−jπ/4}/2 − ∫_0^√X e^{−jτ²}dτ): the
// rest is continuous through δ = 0), i.e. the analytic continuation from that side.
C cot_f(double u, double n, double kl, double a, int side, double band) {
  const double s = std::sin(u);
  const double m = std::round(u / kPi);
  const double delta = 2.0 * n * (u - m * kPi);
  const int geometric = delta < 0.0 ? -1 : 1;
  const int want = side != 0 && std::abs(delta) < band ? side : geometric;
  if (std::abs(s) < 1e-12) return double(want) * n * std::sqrt(kTwoPi * kl) * kEjPi4;
  const double x = kl * a;
  const double cot = std::cos(u) / s;
  C term = cot * utd_transition(x);
  if (want != geometric) term -= 2.0 * cot * C(0.0, 1.0) * std::sqrt(kPi * std::max(x, 0.0)) * std::polar(1.0, x) * kEmjPi4;
  return term;
}

// a^±(β) = 2cos²((2nπN^± − β)/2), N^± the integer nearest to (β ± π)/(2nπ).
double a_plus(double beta, double n) {
  const double big_n = std::round((beta + kPi) / (2.0 * n * kPi));
  const double c = std::cos((2.0 * n * kPi * big_n - beta) / 2.0);
  return 2.0 * c * c;
}
double a_minus(double beta, double n) {
  const double big_n = std::round((beta - kPi) / (2.0 * n * kPi));
  const double c = std::cos((2.0 * n * kPi * big_n - beta) / 2.0);
  return 2.0 * c * c;
}

}  // namespace

C fresnel_tail(double a) {
  a = std::max(a, 0.0);
  return std::polar(1.0, -a * a) * scaled_tail(a * a);
}

C fresnel_from_minus_infinity(double a) {
  if (a < 0.0) return fresnel_tail(-a);  // the integrand is even
  return kSqrtPi * kEmjPi4 - fresnel_tail(a);
}

C utd_transition(double x) {
  x = std::max(x, 0.0);
  return C(0.0, 2.0) * std::sqrt(x) * scaled_tail(x);
}

UtdCoefficients wedge_diffraction(double n, double phi, double phi_prime, double beta0, double l, double k,
                                  const FresnelCoefficients& face0, const FresnelCoefficients& facen,
                                  const GeometricOpticsSides& sides) {
  const double kl = k * l;
  const double bm = phi - phi_prime, bp = phi + phi_prime;
  const double two_n = 2.0 * n;
  const double band = sides.band_rad;
  // Incident shadow boundary terms (the same for both polarizations) and the two reflection boundary terms.
  const C t1 = cot_f((kPi + bm) / two_n, n, kl, a_plus(bm, n), sides.incident, band);
  const C t2 = cot_f((kPi - bm) / two_n, n, kl, a_minus(bm, n), sides.incident, band);
  const C t0 = cot_f((kPi - bp) / two_n, n, kl, a_minus(bp, n), sides.reflected_face0, band);  // φ + φ' = π
  const C tn = cot_f((kPi + bp) / two_n, n, kl, a_plus(bp, n), sides.reflected_facen, band);   // (2n − 1)π
  const C front = -kEmjPi4 / (two_n * std::sqrt(kTwoPi * k) * std::sin(beta0));
  return {front * (t1 + t2 + face0.te * t0 + facen.te * tn), front * (t1 + t2 + face0.tm * t0 + facen.tm * tn),
          front * (t1 + t2)};
}

double utd_min_transition_argument(double n, double phi, double phi_prime, double kl) {
  const double bm = phi - phi_prime, bp = phi + phi_prime;
  return kl * std::min(std::min(a_plus(bm, n), a_minus(bm, n)), std::min(a_minus(bp, n), a_plus(bp, n)));
}

}  // namespace rfidray
