// `rfidray bench`: where the results go. A quick run must never write into the committed full-run results
// (bench/results/); --dry-run prints the chosen directory and commands without running or creating anything,
// so the selection is tested without the minutes a real run takes.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "tests/support/run_rfidray.h"
#include "tests/support/scratch_dir.h"

namespace rfidray {
namespace {

namespace fs = std::filesystem;

using testing::ScratchDir;

// Runs `rfidray bench ARGS --dry-run` with the scratch directory as the current directory.
testing::CliResult dry_run(const ScratchDir& d, const std::string& args) {
  return testing::run_rfidray("bench --dry-run " + args, "cd '" + d.path().string() + "' && ");
}

TEST(BenchCli, QuickRunGoesToScratchNotCommittedResults) {
  ScratchDir d("bench_cli");
  const auto r = dry_run(d, "--quick");
  ASSERT_EQ(r.status, 0) << r.output;
  const std::string dir = fs::weakly_canonical(d.path()).string();
  EXPECT_NE(r.output.find("results would go to " + dir + "/out/bench-quick\n"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("bench/results"), std::string::npos) << r.output;
  // Every program is told the scratch directory.
  EXPECT_NE(r.output.find("bench_sweep --out '" + dir + "/out/bench-quick' --quick"), std::string::npos) << r.output;
  // A dry run creates nothing.
  EXPECT_TRUE(fs::is_empty(d.path()));
}

TEST(BenchCli, FullRunWritesTheCommittedResultsAndOutputWins) {
  ScratchDir d("bench_cli");
  const std::string dir = fs::weakly_canonical(d.path()).string();
  auto r = dry_run(d, "");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("results would go to " + dir + "/bench/results\n"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("bench-quick"), std::string::npos) << r.output;
  r = dry_run(d, "--quick -o elsewhere --only bench_sweep");
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_NE(r.output.find("results would go to " + dir + "/elsewhere\n"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("bench_rays"), std::string::npos) << r.output;  // --only respected
  EXPECT_TRUE(fs::is_empty(d.path()));
}

TEST(BenchCli, UnknownProgramIsAnInputError) {
  ScratchDir d("bench_cli");
  const auto r = dry_run(d, "--only bench_nothing");
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("bench_nothing"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace rfidray
