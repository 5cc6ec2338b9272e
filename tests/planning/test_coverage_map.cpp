// coverage()'s work items (planning/coverage_map.h): every thread gets work on a small map, a large map keeps
// items of 256, and no item is below what a batch needs to share its plane and edge pairs.
#include <gtest/gtest.h>

#include <algorithm>

#include "planning/coverage_map.h"

namespace rfidray::planning {
namespace {

TEST(CoverageWorkItems, EveryThreadGetsWorkAndBatchesStayShareable) {
  for (int threads : {1, 2, 3, 8}) {
    for (size_t cells : {0u, 1u, 2u, 7u, 40u, 63u, 64u, 65u, 127u, 200u, 400u, 1024u, 2048u, 10000u, 1000000u}) {
      const size_t per_item = coverage_cells_per_item(cells, threads);
      const size_t items = (cells + per_item - 1) / per_item;
      ASSERT_GE(per_item, 1u) << cells;
      EXPECT_LE(per_item, 256u) << cells;
      if (cells < 64) {
        // No item of such a map shares pairs (from 64 tags on): one item per thread, every thread busy.
        EXPECT_EQ(items, std::min<size_t>(static_cast<size_t>(threads), cells)) << cells << ", " << threads;
        if (cells > 0) EXPECT_LE(per_item * static_cast<size_t>(threads), cells + static_cast<size_t>(threads) - 1);
        continue;
      }
      EXPECT_EQ(per_item % 16, 0u) << cells << " cells, " << threads << " threads";
      EXPECT_GE(per_item, 64u) << cells;
      // As many items as there are threads whenever 64-cell items allow it (200 cells were one item of 256).
      EXPECT_GE(items, std::min<size_t>(static_cast<size_t>(threads), (cells + 63) / 64)) << cells << ", " << threads;
    }
  }
  EXPECT_EQ(coverage_cells_per_item(1000000, 2), 256u);  // a large map: the compact patches it always had
  EXPECT_EQ(coverage_cells_per_item(200, 2), 64u);       // 4 items for 2 threads, not one of 256
  EXPECT_EQ(coverage_cells_per_item(42, 2), 21u);        // 2 items, not one of 64 on one thread
}

}  // namespace
}  // namespace rfidray::planning
