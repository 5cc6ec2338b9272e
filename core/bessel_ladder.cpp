#include "core/bessel_ladder.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rfidray {

void bessel_j_ladder(double nu0, double x, int count, double* out) {
  if (!(x > 0.0) || !std::isfinite(x)) throw std::invalid_argument("bessel_j_ladder: x must be finite and > 0");
  if (!(nu0 >= 0.0) || count < 0) throw std::invalid_argument("bessel_j_ladder: nu0 >= 0 and count >= 0 needed");
  if (count == 0) return;
  // Start well above both the highest order wanted and x (Numerical Recipes' bessj: +√(40 n)); the error of the
  // start decays like J_top/Y_top, far below 1e-16 at this margin.
  const int top = std::max(count, static_cast<int>(x) + 1);
  const int start = top + 20 + static_cast<int>(std::sqrt(40.0 * top));
  double j_above = 0.0, j = 1e-300;  // J_{ν0+k+1}, J_{ν0+k} up to a common factor
  for (int k = start; k >= 1; --k) {
    const double j_below = (2.0 * (nu0 + k) / x) * j - j_above;  // J_{ν0+k−1}
    j_above = j;
    j = j_below;
    if (std::abs(j) > 1e250) {  // rescale everything kept so far
      j *= 1e-250;
      j_above *= 1e-250;
      for (int r = k; r < count; ++r) out[r] *= 1e-250;
    }
    if (k - 1 < count) out[k - 1] = j;
  }
  int largest = 0;
  for (int r = 1; r < count; ++r)
    if (std::abs(out[r]) > std::abs(out[largest])) largest = r;
  const double scale = std::cyl_bessel_j(nu0 + largest, x) / out[largest];
  for (int r = 0; r < count; ++r) out[r] *= scale;
}

}  // namespace rfidray
