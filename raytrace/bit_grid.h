#pragma once
// Occupancy bitmaps of the plane searches (raytrace/path_finder.h): a row-major grid of cells, one bit each,
// packed in 64-bit words. Pure functions; thread-safe.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace rfidray {

// Whether any cell of the inclusive rectangle [iu0, iu1] × [iv0, iv1] is set in the grid whose cell (iu, iv) is
// bit first_bit + iv·row_cells + iu of `bits`. A rectangle of more than max_scan cells is not scanned and counts
// as set (a large one is seldom empty, and the callers only use "empty" to skip work).
inline bool any_bit_in_rect(const std::vector<uint64_t>& bits, size_t first_bit, int row_cells, int iu0, int iu1,
                            int iv0, int iv1, long max_scan = 4096) {
  if (static_cast<long>(iu1 - iu0 + 1) * (iv1 - iv0 + 1) > max_scan) return true;
  for (int iv = iv0; iv <= iv1; ++iv) {
    size_t first = first_bit + static_cast<size_t>(iv) * row_cells + iu0;
    const size_t last = first_bit + static_cast<size_t>(iv) * row_cells + iu1;  // inclusive
    while (first <= last) {
      const size_t word = first / 64, end = std::min(last, word * 64 + 63);
      const int from = static_cast<int>(first % 64), count = static_cast<int>(end - first + 1);
      const uint64_t mask = (count == 64 ? ~uint64_t{0} : ((uint64_t{1} << count) - 1)) << from;
      if (bits[word] & mask) return true;
      first = end + 1;
    }
  }
  return false;
}

}  // namespace rfidray
