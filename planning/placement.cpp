#include "planning/placement.h"

#include <algorithm>
#include <bit>
#include <stdexcept>

namespace rfidray::planning {

CoverSets::CoverSets(size_t candidates, size_t tags)
    : candidates_(candidates), tags_(tags), words_((tags + 63) / 64), bits_(candidates * words_, 0) {}

void CoverSets::set(size_t c, size_t t) { bits_[c * words_ + t / 64] |= uint64_t{1} << (t % 64); }

bool CoverSets::covers(size_t c, size_t t) const { return (bits_[c * words_ + t / 64] >> (t % 64)) & 1u; }

size_t CoverSets::covered(const std::vector<size_t>& chosen) const {
  size_t n = 0;
  for (size_t w = 0; w < words_; ++w) {
    uint64_t u = 0;
    for (size_t c : chosen) u |= bits_[c * words_ + w];
    n += static_cast<size_t>(std::popcount(u));
  }
  return n;
}

Placement place_greedy_swap(const CoverSets& sets, size_t k) {
  const size_t n = sets.candidates(), words = sets.words();
  if (k == 0 || k > n) throw std::invalid_argument("place_greedy_swap: need 1 <= K <= candidates");
  Placement out;
  std::vector<uint64_t> union_bits(words, 0);
  std::vector<char> taken(n, 0);
  // Greedy: the largest marginal gain, lowest index on ties.
  for (size_t step = 0; step < k; ++step) {
    size_t best = n, best_gain = 0;
    for (size_t c = 0; c < n; ++c) {
      if (taken[c]) continue;
      const uint64_t* r = sets.row(c);
      size_t gain = 0;
      for (size_t w = 0; w < words; ++w) gain += static_cast<size_t>(std::popcount(r[w] & ~union_bits[w]));
      if (best == n || gain > best_gain) best = c, best_gain = gain;
    }
    taken[best] = 1;
    out.chosen.push_back(best);
    const uint64_t* r = sets.row(best);
    for (size_t w = 0; w < words; ++w) union_bits[w] |= r[w];
    out.greedy_curve.push_back(sets.covered(out.chosen));
  }
  out.covered = out.greedy_curve.back();
  // Swaps: the best (position, candidate) replacement while it covers more.
  for (;;) {
    size_t best_pos = k, best_c = n, best_cov = out.covered;
    std::vector<uint64_t> rest(words);
    for (size_t i = 0; i < k; ++i) {
      std::fill(rest.begin(), rest.end(), 0);
      for (size_t j = 0; j < k; ++j)
        if (j != i) {
          const uint64_t* r = sets.row(out.chosen[j]);
          for (size_t w = 0; w < words; ++w) rest[w] |= r[w];
        }
      for (size_t c = 0; c < n; ++c) {
        if (taken[c]) continue;
        const uint64_t* r = sets.row(c);
        size_t cov = 0;
        for (size_t w = 0; w < words; ++w) cov += static_cast<size_t>(std::popcount(rest[w] | r[w]));
        if (cov > best_cov) best_pos = i, best_c = c, best_cov = cov;
      }
    }
    if (best_pos == k) break;
    taken[out.chosen[best_pos]] = 0;
    taken[best_c] = 1;
    out.chosen[best_pos] = best_c;
    out.covered = best_cov;
    ++out.swaps;
  }
  out.heuristic_covered = out.covered;
  return out;
}

double subset_count(size_t n, size_t k) {
  double c = 1.0;
  for (size_t i = 1; i <= k; ++i) c = c * static_cast<double>(n - k + i) / static_cast<double>(i);
  return c;
}

Placement place_antennas(const CoverSets& sets, size_t k, double exact_limit) {
  Placement out = place_greedy_swap(sets, k);
  const size_t n = sets.candidates(), words = sets.words();
  if (subset_count(n, k) > exact_limit) return out;
  out.exact = true;
  // Depth-first over increasing index tuples, the union of the first d picks kept per depth.
  std::vector<size_t> pick(k);
  std::vector<std::vector<uint64_t>> unions(k + 1, std::vector<uint64_t>(words, 0));
  size_t best = out.covered;
  std::vector<size_t> best_pick;
  size_t depth = 0;
  pick[0] = 0;
  for (;;) {
    if (pick[depth] > n - (k - depth)) {  // no room for the remaining picks: back up
      if (depth == 0) break;
      --depth;
      ++pick[depth];
      continue;
    }
    const uint64_t* r = sets.row(pick[depth]);
    for (size_t w = 0; w < words; ++w) unions[depth + 1][w] = unions[depth][w] | r[w];
    if (depth + 1 == k) {
      size_t cov = 0;
      for (size_t w = 0; w < words; ++w) cov += static_cast<size_t>(std::popcount(unions[k][w]));
      if (cov > best) best = cov, best_pick = pick;
      ++pick[depth];
    } else {
      ++depth;
      pick[depth] = pick[depth - 1] + 1;
    }
  }
  if (!best_pick.empty()) {
    out.chosen = best_pick;
    out.covered = best;
  }
  return out;
}

}  // namespace rfidray::planning
