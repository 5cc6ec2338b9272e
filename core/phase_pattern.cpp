#include "core/phase_pattern.h"

#include <cmath>
#include <numbers>

namespace rfidray {

void draw_phase_ripple(PhasePattern& pattern, double rms_rad, double scale_rad, double spread, Rng& rng) {
  const int top = std::max(1, static_cast<int>(std::lround(std::numbers::pi / scale_rad)));
  const int first = (top + 1) / 2;
  std::normal_distribution<double> unit(0.0, 1.0);
  // This element's RMS: log-normal about the median rms_rad (elements of one kind differ).
  const double rms = rms_rad * std::exp(spread * unit(rng));
  // E[φ²] over azimuth = Σ_{n=first..top} (c_n² + s_n²) / 2 = rms² (each coefficient of variance rms²/count).
  const double sd = rms / std::sqrt(static_cast<double>(top - first + 1));
  pattern.ripple_rms_rad = rms_rad;
  pattern.ripple_scale_rad = scale_rad;
  pattern.ripple_spread = spread;
  pattern.ripple_cos_rad.assign(top, 0.0);
  pattern.ripple_sin_rad.assign(top, 0.0);
  for (int n = first; n <= top; ++n) {
    pattern.ripple_cos_rad[n - 1] = sd * unit(rng);
    pattern.ripple_sin_rad[n - 1] = sd * unit(rng);
  }
}

}  // namespace rfidray
