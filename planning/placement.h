#pragma once
// Choosing K antenna poses among candidates to cover the most tags (maximum coverage). A candidate covers a tag
// when it reads it with probability ≥ p per pass (planning/coverage_map.h decides; here it is a boolean matrix).
// Coverage is monotone submodular, so greedy selection — each step the candidate that adds the most tags — is
// within 1 − 1/e of the optimum (Nemhauser, Wolsey, Fisher, Math. Programming 14, 1978); swap refinement then
// replaces one chosen candidate by an unchosen one while that covers more (best swap first), which reaches the
// optimum in many cases where greedy does not, but not in all (a 1-swap local optimum; tests/io/test_placement.cpp
// counts how often on random instances). So when the K-subsets are few enough (≤ exact_limit), every one is
// tried and the best kept: the answer is then the optimum. Ties go to the earlier choice (greedy's, then the
// lexicographically first subset), so the result is deterministic. Pure, thread-compatible.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rfidray::planning {

// Which tags each candidate covers, as bit sets (one bit per tag).
class CoverSets {
 public:
  CoverSets(size_t candidates, size_t tags);
  void set(size_t candidate, size_t tag);
  bool covers(size_t candidate, size_t tag) const;
  size_t candidates() const { return candidates_; }
  size_t tags() const { return tags_; }
  // Tags covered by at least one of `chosen`.
  size_t covered(const std::vector<size_t>& chosen) const;
  const uint64_t* row(size_t candidate) const { return &bits_[candidate * words_]; }
  size_t words() const { return words_; }

 private:
  size_t candidates_, tags_, words_;
  std::vector<uint64_t> bits_;
};

struct Placement {
  std::vector<size_t> chosen;        // candidate indices, in the order greedy picked them (swaps replace in place)
  size_t covered = 0;                // tags covered by `chosen`
  std::vector<size_t> greedy_curve;  // tags covered by the first k greedy picks, k = 1 … K
  size_t swaps = 0;                  // improving swaps applied after greedy
  size_t heuristic_covered = 0;      // tags covered after greedy + swaps
  bool exact = false;                // every K-subset was tried: `covered` is the optimum
};

// K (≥ 1, ≤ candidates) poses: greedy, then swaps until none improves.
Placement place_greedy_swap(const CoverSets& sets, size_t k);

// greedy + swaps, then, when C(candidates, K) ≤ exact_limit, the best of every K-subset if it covers more.
Placement place_antennas(const CoverSets& sets, size_t k, double exact_limit = 1e6);

// C(n, k) as a double (inf when it overflows).
double subset_count(size_t n, size_t k);

}  // namespace rfidray::planning
