#include "planning/placement_bound.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <stdexcept>

#include "planning/placement.h"
#include "localization/cramer_rao.h"

namespace rfidray::planning {
namespace {

// The bound of one cell under the (ascending) set: informations summed in that order.
std::optional<double> cell_bound(const InformationSets& s, const std::vector<size_t>& sorted, size_t cell) {
  double sum[6] = {0, 0, 0, 0, 0, 0};
  for (size_t c : sorted) {
    const double* v = s.at(c, cell);
    for (int j = 0; j < 6; ++j) sum[j] += v[j];
  }
  return localization::position_bound_m(localization::unpack_information(sum), s.height_known());
}

// The score of `chosen` (any order), visiting the cells in `order`; with `beat`, nullopt as soon as the choice
// cannot be better than it (more unlocalized cells, or as many with a worst bound already ≥ beat's).
std::optional<BoundScore> evaluate(const InformationSets& s, std::vector<size_t> chosen, const std::vector<size_t>& order,
                                   const BoundScore* beat) {
  std::sort(chosen.begin(), chosen.end());
  const size_t n = s.cells();
  const size_t beat_missing = beat ? n - beat->localized : n;
  size_t missing = 0;
  double worst = -1.0;
  for (size_t cell : order) {
    const std::optional<double> b = cell_bound(s, chosen, cell);
    if (b)
      worst = std::max(worst, *b);
    else
      ++missing;
    if (beat && (missing > beat_missing || (missing == beat_missing && beat->localized > 0 && worst >= beat->worst_m)))
      return std::nullopt;
  }
  BoundScore out;
  out.localized = n - missing;
  out.worst_m = out.localized > 0 ? worst : std::numeric_limits<double>::quiet_NaN();
  return out;
}

// Cells hardest first under `chosen` (unlocalized, then by decreasing bound; index order on ties): the order in
// which a rival choice fails soonest.
std::vector<size_t> hardest_first(const InformationSets& s, const std::vector<size_t>& chosen) {
  std::vector<size_t> order(s.cells());
  std::iota(order.begin(), order.end(), size_t{0});
  if (chosen.empty()) return order;
  const std::vector<double> b = s.bounds_m(chosen);
  auto key = [&](size_t i) { return std::isfinite(b[i]) ? b[i] : std::numeric_limits<double>::infinity(); };
  std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) { return key(x) > key(y); });
  return order;
}

}  // namespace

InformationSets::InformationSets(size_t candidates, size_t cells, bool height_known)
    : candidates_(candidates), cells_(cells), height_known_(height_known), info_(candidates * cells * 6, 0.0) {}

std::vector<double> InformationSets::bounds_m(const std::vector<size_t>& chosen) const {
  std::vector<size_t> sorted = chosen;
  std::sort(sorted.begin(), sorted.end());
  std::vector<double> out(cells_, std::numeric_limits<double>::quiet_NaN());
  for (size_t i = 0; i < cells_; ++i)
    if (auto b = cell_bound(*this, sorted, i)) out[i] = *b;
  return out;
}

bool BoundScore::better_than(const BoundScore& o) const {
  if (localized != o.localized) return localized > o.localized;
  return localized > 0 && worst_m < o.worst_m;
}

BoundScore score_choice(const InformationSets& sets, const std::vector<size_t>& chosen) {
  std::vector<size_t> order(sets.cells());
  std::iota(order.begin(), order.end(), size_t{0});
  return *evaluate(sets, chosen, order, nullptr);
}

BoundPlacement place_min_worst_bound(const InformationSets& sets, size_t k, double exact_limit) {
  const size_t n = sets.candidates();
  if (k == 0 || k > n) throw std::invalid_argument("place_min_worst_bound: need 1 <= K <= candidates");
  BoundPlacement out;
  std::vector<char> taken(n, 0);
  // Greedy: the best objective together with those already chosen, lowest index on ties.
  for (size_t step = 0; step < k; ++step) {
    const std::vector<size_t> order = hardest_first(sets, out.chosen);
    size_t best = n;
    BoundScore best_score;
    std::vector<size_t> trial = out.chosen;
    trial.push_back(0);
    for (size_t c = 0; c < n; ++c) {
      if (taken[c]) continue;
      trial.back() = c;
      const std::optional<BoundScore> sc = evaluate(sets, trial, order, best == n ? nullptr : &best_score);
      if (sc && (best == n || sc->better_than(best_score))) best = c, best_score = *sc;
    }
    taken[best] = 1;
    out.chosen.push_back(best);
    out.greedy_curve.push_back(best_score);
  }
  out.score = out.greedy_curve.back();
  // Swaps: the best (position, candidate) replacement while one improves the objective.
  for (;;) {
    const std::vector<size_t> order = hardest_first(sets, out.chosen);
    size_t best_pos = k, best_c = n;
    BoundScore best_score = out.score;
    for (size_t i = 0; i < k; ++i) {
      std::vector<size_t> trial = out.chosen;
      for (size_t c = 0; c < n; ++c) {
        if (taken[c]) continue;
        trial[i] = c;
        const std::optional<BoundScore> sc = evaluate(sets, trial, order, &best_score);
        if (sc && sc->better_than(best_score)) best_pos = i, best_c = c, best_score = *sc;
      }
    }
    if (best_pos == k) break;
    taken[out.chosen[best_pos]] = 0;
    taken[best_c] = 1;
    out.chosen[best_pos] = best_c;
    out.score = best_score;
    ++out.swaps;
  }
  out.heuristic = out.score;
  if (subset_count(n, k) > exact_limit) return out;
  out.exact = true;
  // Every increasing index tuple, each scored against the best so far (the heuristic's to start with).
  const std::vector<size_t> order = hardest_first(sets, out.chosen);
  std::vector<size_t> pick(k);
  std::iota(pick.begin(), pick.end(), size_t{0});
  BoundScore best = out.score;
  std::vector<size_t> best_pick;
  for (;;) {
    if (const std::optional<BoundScore> sc = evaluate(sets, pick, order, &best); sc && sc->better_than(best))
      best = *sc, best_pick = pick;
    size_t i = k;
    while (i > 0 && pick[i - 1] == n - k + i - 1) --i;
    if (i == 0) break;
    ++pick[i - 1];
    for (size_t j = i; j < k; ++j) pick[j] = pick[j - 1] + 1;
  }
  if (!best_pick.empty()) {
    out.chosen = best_pick;
    out.score = best;
  }
  return out;
}

}  // namespace rfidray::planning
