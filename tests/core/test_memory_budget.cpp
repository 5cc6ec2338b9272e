#include "core/memory_budget.h"

#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"

namespace rfidray {
namespace {

TEST(MemoryBudget, SizesInBinaryUnits) {
  EXPECT_EQ(parse_memory_size("4G", "--m"), 4.0 * 1024 * 1024 * 1024);
  EXPECT_EQ(parse_memory_size("512M", "--m"), 512.0 * 1024 * 1024);
  EXPECT_EQ(parse_memory_size("1.5GiB", "--m"), 1.5 * 1024 * 1024 * 1024);
  EXPECT_EQ(parse_memory_size("2e9", "--m"), 2e9);
  EXPECT_EQ(parse_memory_size("1t", "--m"), 1024.0 * 1024 * 1024 * 1024);
  for (const char* bad : {"", "1K", "M", "12Q", "nan", "-1G", "1e400"}) EXPECT_THROW(parse_memory_size(bad, "--m"), InputError) << bad;
}

TEST(MemoryBudget, EstimateAboveTheBudgetThrowsWithBothFigures) {
  const double before = memory_budget_bytes();
  EXPECT_GT(before, 0.0);  // the machine's memory (or +inf where it cannot be read)
  set_memory_budget_bytes(1e9, "--max-memory");
  EXPECT_NO_THROW(check_memory_estimate(0.9e9, "scene: 1 triangles", "x"));
  try {
    check_memory_estimate(2e9, "scene: 6e6 triangles", "330 bytes per triangle");
    ADD_FAILURE() << "no throw";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "scene: 6e6 triangles would need about 2 GB (330 bytes per triangle), more than the memory "
                           "budget of 1 GB (--max-memory; rfidray --max-memory SIZE sets it)");
  }
  set_memory_budget_bytes(before, "this machine's memory");
}

}  // namespace
}  // namespace rfidray
