#include "localization/multipath_allowance.h"

#include <cmath>
#include <limits>

namespace rfidray::loc {

double multipath_phase_rms_rad(std::span<const std::complex<double>> ratio) {
  if (ratio.empty()) return 0.0;
  std::complex<double> mean = 0.0;
  for (const std::complex<double>& r : ratio) {
    const double a = std::abs(r);
    if (!(a > 0.0) || !std::isfinite(a)) return std::numeric_limits<double>::infinity();
    mean += (r * r) / (a * a);  // e^{jε}, ε = 2 arg r
  }
  double sum2 = 0.0;
  for (const std::complex<double>& r : ratio) {
    const double e = std::arg((r * r) * std::conj(mean));  // ε − mean, wrapped to (−π, π]
    sum2 += e * e;
  }
  return std::sqrt(sum2 / static_cast<double>(ratio.size()));
}

}  // namespace rfidray::loc
