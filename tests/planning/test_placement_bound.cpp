// Placement by the worst localization bound (planning/placement_bound.h): the exhaustive answer equals brute force over
// all K-subsets scored independently here; greedy + swaps alone is a local optimum, and a case shows it missing
// the optimum (the objective is not submodular, so there is no 1 − 1/e bound to assert instead).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "planning/placement_bound.h"
#include "localization/cramer_rao.h"

namespace rfidray::planning {
namespace {

// The objective of one subset, from position_bound_m of the informations summed in increasing index order.
BoundScore brute_score(const InformationSets& s, const std::vector<size_t>& sorted) {
  BoundScore out;
  double worst = -1.0;
  for (size_t cell = 0; cell < s.cells(); ++cell) {
    double sum[6] = {0, 0, 0, 0, 0, 0};
    for (size_t c : sorted)
      for (int j = 0; j < 6; ++j) sum[j] += s.at(c, cell)[j];
    if (auto b = localization::position_bound_m(localization::unpack_information(sum), s.height_known()))
      ++out.localized, worst = std::max(worst, *b);
  }
  out.worst_m = out.localized ? worst : std::nan("");
  return out;
}

// The best subset by brute force: more localized cells, then the smaller worst bound.
BoundScore brute_force(const InformationSets& s, size_t k) {
  std::vector<size_t> pick(k);
  for (size_t i = 0; i < k; ++i) pick[i] = i;
  BoundScore best = brute_score(s, pick);
  for (;;) {
    size_t i = k;
    while (i > 0 && pick[i - 1] == s.candidates() - k + i - 1) --i;
    if (i == 0) break;
    ++pick[i - 1];
    for (size_t j = i; j < k; ++j) pick[j] = pick[j - 1] + 1;
    const BoundScore sc = brute_score(s, pick);
    if (sc.localized > best.localized || (sc.localized == best.localized && sc.localized > 0 && sc.worst_m < best.worst_m))
      best = sc;
  }
  return best;
}

void set_info(InformationSets& s, size_t c, size_t cell, const Eigen::Matrix3d& m) {
  const auto p = localization::pack_information(m);
  std::copy(p.begin(), p.end(), s.at(c, cell));
}

// Random small instances (10 candidates, 14 cells, K = 1 … 4): per candidate and cell no information (not read),
// a rank-1 one (a short pass: one direction only, so a cell needs two antennas), or a full-rank one of random
// scale. The exhaustive search equals brute force exactly; greedy + swaps never beats it and is counted.
TEST(PlacementBound, EqualsBruteForceOnSmallCases) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0), scale(1e2, 1e6);
  std::uniform_int_distribution<int> kind(0, 2);
  int cases = 0, heuristic_short = 0;
  for (int trial = 0; trial < 24; ++trial) {
    const bool height_known = trial % 4 != 3;
    InformationSets s(10, 14, height_known);
    for (size_t c = 0; c < 10; ++c)
      for (size_t cell = 0; cell < 14; ++cell) {
        const int kd = kind(rng);
        if (kd == 0) continue;
        Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
        const int rank = kd == 1 ? 1 : 3;
        for (int r = 0; r < rank; ++r) {
          const Eigen::Vector3d g(u(rng), u(rng), u(rng));
          m += scale(rng) * g * g.transpose();
        }
        set_info(s, c, cell, m);
      }
    for (size_t k = 1; k <= 4; ++k) {
      const BoundScore best = brute_force(s, k);
      const BoundPlacement exact = place_min_worst_bound(s, k);
      ASSERT_TRUE(exact.exact);
      EXPECT_EQ(exact.score.localized, best.localized) << "trial " << trial << " K " << k;
      if (best.localized > 0) { EXPECT_EQ(exact.score.worst_m, best.worst_m) << "trial " << trial << " K " << k; }
      // The reported score is the chosen set's.
      const BoundScore check = score_choice(s, exact.chosen);
      EXPECT_EQ(check.localized, exact.score.localized);
      if (check.localized > 0) { EXPECT_EQ(check.worst_m, exact.score.worst_m); }
      const BoundPlacement h = place_min_worst_bound(s, k, 0.0);  // heuristic only
      EXPECT_FALSE(h.exact);
      EXPECT_FALSE(h.score.better_than(best));
      EXPECT_FALSE(h.greedy_curve.back().better_than(h.score));  // swaps never make it worse
      heuristic_short += best.better_than(h.score);
      ++cases;
    }
  }
  std::printf("greedy + swaps below the optimum in %d of %d cases\n", heuristic_short, cases);
}

// A 1-swap local optimum that is not optimal: antennas 0 and 1 each see cells 0–2 along one axis (x, y), antennas
// 2 and 3 cells 3–6 likewise. Alone, none localizes a cell; greedy takes 0 (every single antenna ties), then 1
// (3 cells); no single swap localizes anything, so greedy + swaps stops at 3 cells while {2, 3} localizes 4.
TEST(PlacementBound, SwapsCanMissTheOptimum) {
  InformationSets s(4, 7, true);
  const Eigen::Matrix3d x = 1e4 * Eigen::Vector3d::UnitX() * Eigen::Vector3d::UnitX().transpose();
  const Eigen::Matrix3d y = 1e4 * Eigen::Vector3d::UnitY() * Eigen::Vector3d::UnitY().transpose();
  for (size_t cell = 0; cell < 3; ++cell) set_info(s, 0, cell, x), set_info(s, 1, cell, y);
  for (size_t cell = 3; cell < 7; ++cell) set_info(s, 2, cell, x), set_info(s, 3, cell, y);
  const BoundPlacement h = place_min_worst_bound(s, 2, 0.0);
  EXPECT_EQ(h.chosen, (std::vector<size_t>{0, 1}));
  EXPECT_EQ(h.score.localized, 3u);
  EXPECT_EQ(h.swaps, 0u);
  EXPECT_NEAR(h.score.worst_m, std::sqrt(2.0 / 1e4), 1e-15);  // √(1/J_xx + 1/J_yy)
  const BoundPlacement e = place_min_worst_bound(s, 2);
  EXPECT_TRUE(e.exact);
  EXPECT_EQ(e.chosen, (std::vector<size_t>{2, 3}));
  EXPECT_EQ(e.score.localized, 4u);
  EXPECT_EQ(e.heuristic.localized, 3u);
  // Never an infinite bound: a choice that localizes nothing has none (NaN), and per cell NaN where not localized.
  EXPECT_EQ(score_choice(s, {0}).localized, 0u);
  EXPECT_TRUE(std::isnan(score_choice(s, {0}).worst_m));
  const std::vector<double> b = s.bounds_m({0, 1});
  EXPECT_TRUE(std::isfinite(b[0]));
  EXPECT_TRUE(std::isnan(b[5]));
}

// The worst bound decides once the localized counts tie: the choice whose weakest cell is best constrained.
TEST(PlacementBound, SmallerWorstBoundWins) {
  InformationSets s(3, 2, true);
  const Eigen::Matrix3d i2 = Eigen::Vector3d(1, 1, 0).asDiagonal();  // isotropic in (x, y): bound √(2/J)
  set_info(s, 0, 0, 1e4 * i2), set_info(s, 0, 1, 50 * i2);  // strong on cell 0, weak on cell 1
  set_info(s, 1, 0, 1e2 * i2), set_info(s, 1, 1, 1e3 * i2);
  set_info(s, 2, 0, 1e3 * i2), set_info(s, 2, 1, 1e3 * i2);  // even
  const BoundPlacement one = place_min_worst_bound(s, 1);
  EXPECT_EQ(one.chosen, (std::vector<size_t>{2}));
  EXPECT_NEAR(one.score.worst_m, std::sqrt(2.0 / 1e3), 1e-15);
  // {0, 1}: worst cell 1 at 1050; {0, 2}: cell 1 at 1050; {1, 2}: cell 0 at 1100, the best.
  const BoundPlacement two = place_min_worst_bound(s, 2);
  EXPECT_EQ(two.score.localized, 2u);
  EXPECT_EQ(two.chosen, (std::vector<size_t>{2, 1}));  // greedy's order
  EXPECT_NEAR(two.score.worst_m, std::sqrt(2.0 / 1100.0), 1e-15);
}

}  // namespace
}  // namespace rfidray::planning
