#include "parallel/ranks.h"

namespace rfidray::parallel {

std::pair<size_t, size_t> Ranks::share(size_t n, int r) const {
  // 128-bit products: n·r never overflows for any n that fits in memory.
  const auto at = [&](int k) {
    return static_cast<size_t>(static_cast<unsigned __int128>(n) * static_cast<unsigned>(k) / static_cast<unsigned>(size_));
  };
  const size_t first = at(r);
  return {first, at(r + 1) - first};
}

}  // namespace rfidray::parallel
