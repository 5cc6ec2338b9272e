// The logarithmic capacity (core/logarithmic_capacity.h) against its closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/error.h"
#include "core/logarithmic_capacity.h"
#include "core/units.h"

namespace rfidray {
namespace {

using V = Eigen::Vector2d;

TEST(LogarithmicCapacity, MatchesClosedForms) {
  // Circle (a 720-gon: its capacity is the circle's to ~1e-5), segment w/4, square Γ(1/4)² s / (4π^{3/2}).
  std::vector<V> circle;
  for (int i = 0; i < 720; ++i) circle.emplace_back(0.03 * std::cos(kTwoPi * i / 720), 0.03 * std::sin(kTwoPi * i / 720));
  EXPECT_NEAR(logarithmic_capacity_m(circle) / 0.03, 1.0, 2e-4);
  const std::vector<V> segment{V(0.0, 0.0), V(0.05, 0.0)};
  EXPECT_NEAR(logarithmic_capacity_m(segment) / (0.05 / 4.0), 1.0, 2e-4);
  const double square_factor = std::tgamma(0.25) * std::tgamma(0.25) / (4.0 * std::pow(kPi, 1.5));  // 0.59017
  const std::vector<V> square{V(0, 0), V(0.05, 0), V(0.05, 0.05), V(0, 0.05)};
  EXPECT_NEAR(logarithmic_capacity_m(square) / (square_factor * 0.05), 1.0, 2e-4);
}

TEST(LogarithmicCapacity, MovesAndTurnsWithItsShapeAndScalesWithIt) {
  const std::vector<V> rect{V(0, 0), V(0.08, 0), V(0.08, 0.03), V(0, 0.03)};
  const double base = logarithmic_capacity_m(rect);
  std::vector<V> moved, grown;
  const double c = std::cos(0.7), s = std::sin(0.7);
  for (const V& p : rect) {
    moved.emplace_back(12.0 + c * p.x() - s * p.y(), -3.0 + s * p.x() + c * p.y());
    grown.push_back(40.0 * p);  // 3.2 m: a capacity above 1 m (ln cap > 0) works as well
  }
  EXPECT_NEAR(logarithmic_capacity_m(moved), base, 1e-9);
  EXPECT_NEAR(logarithmic_capacity_m(grown) / (40.0 * base), 1.0, 1e-9);
  // Between the segment along its long side and the circumscribed circle.
  EXPECT_GT(base, 0.08 / 4.0);
  EXPECT_LT(base, 0.5 * std::hypot(0.08, 0.03));
}

TEST(LogarithmicCapacity, RefusesDegenerateOutlines) {
  const std::vector<V> one{V(1, 1), V(1, 1)};
  EXPECT_THROW(logarithmic_capacity_m(one), InputError);
  const std::vector<V> bad{V(0, 0), V(std::nan(""), 1)};
  EXPECT_THROW(logarithmic_capacity_m(bad), InputError);
}

}  // namespace
}  // namespace rfidray
