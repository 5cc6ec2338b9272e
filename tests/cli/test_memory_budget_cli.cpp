// Issue #12: a scene, grid or generated warehouse that would need more than the memory budget (the machine's
// memory, or `rfidray --max-memory SIZE`) is refused before it is allocated, with the estimate, exit 2.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include "tests/support/run_rfidray.h"
#include "tests/support/scratch_dir.h"

namespace rfidray::cli {
namespace {

namespace fs = std::filesystem;
using rfidray::testing::run_rfidray;
const std::string kSource = RFIDRAY_SOURCE_DIR;

bool contains(const std::string& s, const std::string& what) { return s.find(what) != std::string::npos; }

class MemoryBudgetCli : public ::testing::Test {
 protected:
  const testing::ScratchDir scratch_{testing::ScratchDir::current_test_name("membudget")};
  const fs::path dir_ = scratch_.path();
};

TEST_F(MemoryBudgetCli, GeneratedWarehouseOverTheBudgetIsRefusedBeforeAnyOutput) {
  const fs::path obj = dir_ / "big.obj";
  // 400 × 400 racks: about 1.4e7 triangles, ~1 GB at 70 bytes each; well under the fixed 2e8 limit.
  const auto r = run_rfidray("--max-memory 64M gen-warehouse --preset parametric --rows 400 --racks 400 -o " + obj.string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "field 'size': about 1.408e+07 triangles would need about")) << r.output;
  EXPECT_TRUE(contains(r.output, "memory budget of 0.0671 GB (--max-memory")) << r.output;
  EXPECT_FALSE(fs::exists(obj));
  // The same run within a budget that fits starts writing (a smaller warehouse, to stay quick).
  const auto ok = run_rfidray("gen-warehouse --preset parametric --rows 4 --racks 4 -o " + obj.string() + " --max-memory 64M");
  EXPECT_EQ(ok.status, 0) << ok.output;
  EXPECT_TRUE(fs::exists(obj));
}

TEST_F(MemoryBudgetCli, SceneOverTheBudgetNamesItsTriangles) {
  const fs::path obj = dir_ / "w.obj";
  ASSERT_EQ(run_rfidray("gen-warehouse --preset parametric --rows 10 --racks 10 -o " + obj.string()).status, 0);
  const auto r = run_rfidray("--max-memory 2M link --scene " + obj.string() + " --antenna 0,0,1 --tag 1,1,1");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "triangles would need about")) << r.output;
  EXPECT_TRUE(contains(r.output, "330 bytes per triangle")) << r.output;
  // The paper warehouse (1 154 triangles, 0.4 MB) fits the same budget.
  const auto ok = run_rfidray("--max-memory 2M link --scene " + kSource + "/scenes/paper_warehouse.obj --antenna 0,0,1 --tag 1,1,1");
  EXPECT_EQ(ok.status, 0) << ok.output;
}

TEST_F(MemoryBudgetCli, CoverageGridOverTheBudgetIsRefused) {
  const auto r = run_rfidray("coverage " + kSource + "/scenes/paper_planning.yaml --plane z=1.2 --step 0.01 --antenna fixed "
                             "--max-memory 100M -o " + (dir_ / "cov").string());
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_TRUE(contains(r.output, "3600000 points would need about 0.922 GB (256 bytes per point)")) << r.output;
  EXPECT_FALSE(fs::exists(dir_ / "cov" / "coverage.csv"));
}

TEST_F(MemoryBudgetCli, BadSizesNameTheOption) {
  for (const std::string size : {"1K", "abc", "nan", "-5G", "4X", "inf"}) {
    const auto r = run_rfidray("--max-memory " + size + " link --scene " + kSource +
                               "/scenes/paper_warehouse.obj --antenna 0,0,1 --tag 1,1,1");
    EXPECT_EQ(r.status, 2) << size << ": " << r.output;
    EXPECT_TRUE(contains(r.output, "option --max-memory:")) << size << ": " << r.output;
  }
}

}  // namespace
}  // namespace rfidray::cli
