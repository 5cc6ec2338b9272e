#include "localization/grid.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace rfidray::loc {

Grid make_grid(const Vec3& lo, const Vec3& hi, double min_step_m, long max_points) {
  Grid g;
  g.origin = lo;
  g.step_m = min_step_m;
  const Vec3 span = hi - lo;
  if (!span.allFinite() || !(span.minCoeff() >= 0.0) || !(min_step_m > 0.0) || max_points < 1)
    throw std::invalid_argument("make_grid: a finite box and a positive step and budget are needed");
  for (;;) {
    // Counted in double: a wide box at a fine step has more points per axis than an int holds.
    const Vec3 n = (span / g.step_m).array().floor() + 1.0;
    if (n.prod() <= static_cast<double>(max_points)) {
      g.nx = static_cast<int>(n.x());
      g.ny = static_cast<int>(n.y());
      g.nz = static_cast<int>(n.z());
      break;
    }
    g.step_m *= 1.25;
  }
  // Centre the grid in the box.
  const Vec3 used = g.step_m * Vec3(g.nx - 1, g.ny - 1, g.nz - 1);
  g.origin = lo + 0.5 * ((hi - lo) - used);
  return g;
}

std::vector<long> best_separated(const Grid& grid, const std::vector<double>& value, int count, double separation_m) {
  std::vector<long> order(value.size());
  std::iota(order.begin(), order.end(), 0L);
  std::sort(order.begin(), order.end(), [&](long a, long b) { return value[a] != value[b] ? value[a] < value[b] : a < b; });
  std::vector<long> out;
  for (long i : order) {
    if (static_cast<int>(out.size()) >= count) break;
    if (!std::isfinite(value[i])) break;
    bool far = true;
    for (long j : out) far &= (grid.point(i) - grid.point(j)).norm() >= separation_m;
    if (far) out.push_back(i);
  }
  return out;
}

}  // namespace rfidray::loc
