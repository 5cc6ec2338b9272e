#pragma once
// The exact two-dimensional field scattered by a perfectly conducting circular cylinder (radius a) lit by a line
// source parallel to its axis: the eigenfunction series (Harrington, *Time-Harmonic Electromagnetic Fields*,
// §5.10; Balanis, *Advanced Engineering Electromagnetics*, §11.5). It is what level `full` puts in place of ray
// optics for a thin metal post (a rack upright: raytrace/thin_posts.h), which is a sub-wavelength scatterer, not
// a shadow: 5–30 cm behind a 5 cm post the field is 0.25–0.63 of free space (FDTD, docs/fullwave.md), where rays
// give nothing at all.
//
// With the incident field H0^(2)(k|ρ − ρ'|) (e^{+jωt}; the source at ρ', φ', the observer at ρ, φ, both outside
// the cylinder) the scattered field is
//   u_s = Σ_{n=0}^{∞} ε_n c_n H_n^(2)(kρ') H_n^(2)(kρ) cos n(φ − φ'),   ε_0 = 1, ε_n = 2,
// with c_n = −J_n(ka)/H_n^(2)(ka) for the soft case (E along the axis, TM_z: E_z = 0 on the surface) and
// c_n = −J'_n(ka)/H'^(2)_n(ka) for the hard case (H along the axis, TE_z: ∂H_z/∂ρ = 0). The series converges
// geometrically, faster the smaller ka and the farther the ends (its n-th term falls as (a²/ρρ')^n): a few terms for
// a 5–10 cm post at UHF (cylinder_terms; at most kCylinderMaxTerms = 48: with both ends within 1.6 radii of the
// axis the last term is still ~1e-10). Near the cylinder the Hankel functions are J_n by Miller's recurrence and
// Y_n by the upward one from the C++17 library's Y_0, Y_1 (std::cyl_neumann, ~0.3 µs a call); from
// x ≥ max(30, 2n²) Hankel's asymptotic expansion (seven terms, A&S 9.2.5–9.2.10: below 1e-8 there), where most
// posts of a warehouse are from most ends. ~1–3 µs for a post.
// Pure functions: thread-safe. Throws std::invalid_argument for ka ≤ 0 or ka > kCylinderMaxKa (the series would need
// more terms than it keeps; a post that thick is not thin).
#include <array>
#include <complex>
#include <limits>

namespace rfidray {

enum class CylinderPolarization { kSoft, kHard };

inline constexpr int kCylinderMaxTerms = 48;
inline constexpr double kCylinderMaxKa = 12.0;

// c_n of both polarizations for one ka, n = 0 … terms − 1 (terms ≤ kCylinderMaxTerms).
struct CylinderCoefficients {
  double ka = 0.0;
  int terms = 0;
  std::array<std::complex<double>, kCylinderMaxTerms> soft{}, hard{};
};
CylinderCoefficients cylinder_coefficients(double ka, int terms = kCylinderMaxTerms);

// How many terms u_s needs for these arguments: beyond n = ka + 2 (where c_n starts to fall) until an estimate of the
// n-th term (small-argument forms of J_n and H_n) is below 1e-16 of the first; at most kCylinderMaxTerms.
int cylinder_terms(double ka, double k_rho_source, double k_rho_observer);

// u_s above for k ρ' = `k_rho_source`, k ρ = `k_rho_observer` (each ≥ ka; a smaller value is taken as ka: an end
// inside the cylinder is on its surface) and φ − φ' = `delta_phi_rad`, with c.terms terms.
std::complex<double> cylinder_scattered(const CylinderCoefficients& c, CylinderPolarization polarization,
                                        double k_rho_source, double k_rho_observer, double delta_phi_rad);
// Both polarizations at once (the Hankel functions are shared).
struct CylinderField {
  std::complex<double> soft, hard;
};
CylinderField cylinder_scattered(const CylinderCoefficients& c, double k_rho_source, double k_rho_observer,
                                 double delta_phi_rad);

// J_n(x) for n = 0 … count − 1, x > 0, by Miller's backward recurrence normalized by J_0 + 2 Σ J_2k = 1
// (A&S 9.12; stable for every order, unlike the upward recurrence beyond n > x).
void bessel_j_orders(double x, int count, double* out);

// H_n^(2)(x) for n = 0 … count − 1 (count ≤ kCylinderMaxTerms + 1), x > 0: the Bessel functions or, from
// x ≥ max(30, 2 s²), Hankel's expansion (above), s = `significant` (default: count). Orders from s on may then be
// far off (the expansion diverges for n² ≫ x): only for terms that the caller's c_n make negligible.
void hankel2_orders(double x, int count, std::complex<double>* out, int significant = -1);

// An upper bound of |u_s| / |H0_far(kρ' + kρ)| (hankel2_zero_far below) for both polarizations and every φ − φ', for
// every cylinder of ka ≤ ka_max and both kρ', kρ ≥ kCylinderBoundMinX: what lets raytrace/post_scattering.cpp skip a
// post whose path would be dropped anyway before summing its series. With |c_n| ≤ C_n and |H_n(x)| ≤ √(M_n/x),
//   |u_s| ≤ Σ_n ε_n C_n M_n / √(kρ' kρ),   |H0_far(x)| = √(2/(πx)),
// M_0 = 2/π and M_n = x₀ |H_n(x₀)|² at x₀ = kCylinderBoundMinX for n ≥ 1: x |H_n(x)|² increases towards 2/π for
// n = 0 and decreases for n ≥ 1 (Nicholson's formula; Watson, "A Treatise on the Theory of Bessel Functions",
// §13.74; DLMF §10.18(iii)). C_n = |c_n(ka_max)| where |c_n| grows with ka on (0, ka_max] — soft n = 0 below Y_0's
// first zero (0.8936), soft n ≥ 1 and hard n = 0 (= soft c_1) below 2.197 (Y_1's) or n, hard n ≥ 1 below n: there
// J_n, Y_n keep their signs and Y_n/J_n (or Y'_n/J'_n) moves monotonically, by the Wronskian 2/(πx) — and C_n = 1
// otherwise (|c_n| ≤ 1 always: |J| ≤ |H|). It carries 1 % more for the rounding of the series and of its Hankel
// expansion (tests/core/test_cylinder_scattering.cpp checks it against the series). Value type; thread-safe once
// built; the constructor throws std::invalid_argument for ka_max ≤ 0 or > kCylinderMaxKa.
inline constexpr double kCylinderBoundMinX = 10.0;
struct CylinderBoundRatios {
  double soft, hard;
};
class CylinderScatteringBound {
 public:
  CylinderScatteringBound() = default;  // bounds nothing: ratio() is +∞
  explicit CylinderScatteringBound(double ka_max);
  // The bound of each polarization for kρ' = `k_rho_source`, kρ = `k_rho_observer`; +∞ unless both are ≥
  // kCylinderBoundMinX. (A thin post's hard bound is far below its soft one: c_n^hard ~ (ka)², c_0^soft ~ 1/ln ka.)
  CylinderBoundRatios ratio(double k_rho_source, double k_rho_observer) const;

 private:
  double soft_sum_ = std::numeric_limits<double>::infinity();  // Σ ε_n C_n M_n per polarization
  double hard_sum_ = std::numeric_limits<double>::infinity();
};

// The two-dimensional free-space field at distance x/k far from a line source, H0^(2)(x) ≈ √(2/πx) e^{−j(x − π/4)}:
// what maps a two-dimensional solution onto a point source's (raytrace/post_scattering.cpp).
std::complex<double> hankel2_zero_far(double x);

}  // namespace rfidray
