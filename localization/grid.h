#pragma once
// A regular search grid over a box (z collapsed when the height is known), with a point budget.
#include <vector>

#include "core/geometry.h"

namespace rfidray::loc {

struct Grid {
  Vec3 origin = Vec3::Zero();
  double step_m = 0.0;
  int nx = 1, ny = 1, nz = 1;
  long size() const { return static_cast<long>(nx) * ny * nz; }
  Vec3 point(long i) const {
    const long ix = i % nx, iy = (i / nx) % ny, iz = i / (static_cast<long>(nx) * ny);
    return origin + step_m * Vec3(static_cast<double>(ix), static_cast<double>(iy), static_cast<double>(iz));
  }
};

// Grid covering [lo, hi] with step ≥ min_step_m, coarsened until it has at most max_points points (any finite box:
// the counts are taken in double). Throws std::invalid_argument for a non-finite or inverted box, a step ≤ 0 or
// max_points < 1 (callers check their inputs first: localize_request.h).
Grid make_grid(const Vec3& lo, const Vec3& hi, double min_step_m, long max_points);

// Indices of the `count` best (smallest) values that are at least `separation_m` apart, best first.
std::vector<long> best_separated(const Grid& grid, const std::vector<double>& value, int count, double separation_m);

}  // namespace rfidray::loc
