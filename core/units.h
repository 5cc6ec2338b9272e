#pragma once
// Physical constants and unit conversions. Names carry units where ambiguity bites.
#include <cmath>
#include <numbers>

namespace rfidray {

inline constexpr double kSpeedOfLight_m_s = 299792458.0;
inline constexpr double kVacuumPermittivity_F_m = 8.8541878128e-12;
inline constexpr double kPi = std::numbers::pi;
inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

inline double wavelength_m(double frequency_hz) { return kSpeedOfLight_m_s / frequency_hz; }
inline double wavenumber_rad_m(double frequency_hz) { return kTwoPi / wavelength_m(frequency_hz); }

// exp rather than pow(10, ·): the same value to an ulp, several times cheaper in per-path loops.
inline double db_to_linear(double db) { return std::exp(db * (std::numbers::ln10 / 10.0)); }
inline double linear_to_db(double lin) { return 10.0 * std::log10(lin); }
inline double dbm_to_watt(double dbm) { return std::pow(10.0, (dbm - 30.0) / 10.0); }
inline double watt_to_dbm(double w) { return 10.0 * std::log10(w) + 30.0; }

// Wraps an angle to [0, 2π).
inline double wrap_to_2pi(double rad) {
  double r = std::fmod(rad, kTwoPi);
  if (r < 0.0) r += kTwoPi;
  if (r >= kTwoPi) r = 0.0;  // fmod can return 2π - ε + 2π rounding to 2π
  return r;
}
// Wraps an angle to (-π, π].
inline double wrap_to_pi(double rad) {
  double r = wrap_to_2pi(rad);
  return r > kPi ? r - kTwoPi : r;
}

}  // namespace rfidray
