#pragma once
// Choosing K antenna poses among candidates to minimise the worst localization bound over the cells
// (`rfidray place --objective worst-bound`). Per candidate and cell the input is the position information S of
// that candidate's pass (localization/cramer_rao.h; planning/coverage_map.h fills it; zero for a fixed antenna). Chosen
// antennas have offsets of their own, so their informations add: the bound of a cell under a choice C is
// position_bound_m(Σ_{c∈C} S_c), summed in increasing candidate index so that it is a function of the set alone.
//
// A cell that the chosen antennas do not localize (no read, or a pass that fixes no position) has an infinite
// bound, so the objective is lexicographic: first the most cells with a finite bound ("localized"), then the
// smallest worst bound over them. No infinity is ever reported: a choice that localizes nothing has no worst
// bound (`worst_m` is then NaN and callers print nothing).
//
// This min-max objective is not submodular (adding an antenna can lower the worst bound by a lot only together
// with another), so greedy selection has no 1 − 1/e guarantee here; greedy (each step the candidate giving the
// best objective with those already chosen) is followed by swaps (best first) while one improves, a 1-swap local
// optimum that can miss the optimum (tests/io/test_placement_bound.cpp shows a case). When C(candidates, K) ≤
// exact_limit every K-subset is scored — pruned as soon as a subset cannot beat the best so far — and the best
// kept: the answer is then the optimum. Ties go to the earlier choice (greedy's lowest index, then the
// lexicographically first subset). Deterministic; pure, thread-compatible.
#include <cstddef>
#include <vector>

namespace rfidray::planning {

// The per-candidate, per-cell information matrices, packed 6 per cell (localization::pack_information).
class InformationSets {
 public:
  InformationSets(size_t candidates, size_t cells, bool height_known);
  // The 6 packed numbers of (candidate, cell).
  double* at(size_t candidate, size_t cell) { return &info_[(candidate * cells_ + cell) * 6]; }
  const double* at(size_t candidate, size_t cell) const { return &info_[(candidate * cells_ + cell) * 6]; }
  size_t candidates() const { return candidates_; }
  size_t cells() const { return cells_; }
  bool height_known() const { return height_known_; }
  // The bound of every cell under `chosen` (NaN where not localized).
  std::vector<double> bounds_m(const std::vector<size_t>& chosen) const;

 private:
  size_t candidates_, cells_;
  bool height_known_;
  std::vector<double> info_;
};

// The objective of one choice: more localized cells first, then the smaller worst bound.
struct BoundScore {
  size_t localized = 0;  // cells with a finite bound
  double worst_m = 0.0;  // the largest finite bound (NaN when localized == 0)
  bool better_than(const BoundScore& o) const;
};

BoundScore score_choice(const InformationSets& sets, const std::vector<size_t>& chosen);

struct BoundPlacement {
  std::vector<size_t> chosen;            // candidate indices, in greedy's order (swaps replace in place)
  BoundScore score;                      // of `chosen`
  std::vector<BoundScore> greedy_curve;  // after the first k greedy picks, k = 1 … K
  size_t swaps = 0;                      // improving swaps applied after greedy
  BoundScore heuristic;                  // after greedy + swaps
  bool exact = false;                    // every K-subset was scored: `score` is the optimum
};

// K (≥ 1, ≤ candidates): greedy, swaps, and the exhaustive search when C(candidates, K) ≤ exact_limit.
BoundPlacement place_min_worst_bound(const InformationSets& sets, size_t k, double exact_limit = 1e6);

}  // namespace rfidray::planning
