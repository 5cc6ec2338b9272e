// loc::make_grid: the search grid of the grid methods stays within its point budget for any finite box, however
// wide (a region of ±1e8 m at a λ/4 step has ~1e9 points per axis, more than an int holds).
#include <gtest/gtest.h>

#include <limits>
#include <stdexcept>

#include "localization/grid.h"

namespace rfidray::loc {
namespace {

TEST(Grid, CoversTheBoxWithinTheBudget) {
  const Grid g = make_grid(Vec3(-1, -2, 0.5), Vec3(1, 2, 0.5), 0.1, 100000);
  EXPECT_EQ(g.step_m, 0.1);  // 21 × 41 points fit
  EXPECT_EQ(g.nx, 21);
  EXPECT_EQ(g.ny, 41);
  EXPECT_EQ(g.nz, 1);
  EXPECT_NEAR(g.point(0).x(), -1.0, 1e-12);
  EXPECT_NEAR(g.point(g.size() - 1).y(), 2.0, 1e-12);
}

TEST(Grid, AWideBoxIsCoarsenedNotOverflowed) {
  const double r = 1e8;  // localize's largest --max-range
  for (const long budget : {60000L, 120000L}) {
    const Grid g = make_grid(Vec3(-r, -r, -r), Vec3(r, r, r), 0.0866 / 4, budget);
    EXPECT_GT(g.nx, 0);
    EXPECT_GT(g.ny, 0);
    EXPECT_GT(g.nz, 0);
    EXPECT_LE(g.size(), budget);
    EXPECT_GE(g.step_m * (g.nx - 1), 0.5 * 2 * r);  // still spans the box (coarsened by 1.25 at a time)
  }
  const Grid planar = make_grid(Vec3(-r, -r, 1), Vec3(r, r, 1), 0.02, 60000);
  EXPECT_EQ(planar.nz, 1);
  EXPECT_LE(planar.size(), 60000);
}

TEST(Grid, NonFiniteBoxIsRefused) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(make_grid(Vec3(-inf, 0, 0), Vec3(inf, 0, 0), 0.1, 1000), std::invalid_argument);
  EXPECT_THROW(make_grid(Vec3(0, 0, 0), Vec3(1, 1, 1), 0.0, 1000), std::invalid_argument);
}

}  // namespace
}  // namespace rfidray::loc
