// `rfidray view` end to end: the paths it reports are the library's, scenario antennas and tags are picked by
// name, and bad input exits 2 naming the option.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <unistd.h>

#include "raytrace/raytraced_channel.h"
#include "tests/support/run_rfidray.h"
#include "tests/support/scratch_dir.h"

namespace rfidray {
namespace {

const std::string kSource = RFIDRAY_SOURCE_DIR;
const std::filesystem::path kThree = "/usr/share/javascript/three/three.min.js";

// Output files of this test program, in a directory removed when it exits.
std::filesystem::path scratch(const std::string& name) {
  static const testing::ScratchDir dir("view_cli");
  return dir / name;
}

// "N links, M paths" from the summary line.
std::pair<int, int> counts(const std::string& out) {
  std::smatch m;
  if (!std::regex_search(out, m, std::regex("(\\d+) links, (\\d+) paths"))) return {-1, -1};
  return {std::stoi(m[1]), std::stoi(m[2])};
}

TEST(ViewCli, SceneModeDrawsTheLibrarysPaths) {
  if (!std::filesystem::exists(kThree)) GTEST_SKIP() << "libjs-three not installed";
  const auto out = scratch("gw.html");
  const auto r = testing::run_rfidray("view --scene " + kSource + "/scenes/ground_wall.obj --antenna 0,0,1 --tag 3,0,1.5 "
                                      "--tag=-4,2,1 -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  const auto scene = load_scene({kSource + "/scenes/ground_wall.obj"}, MaterialAssignment{});
  const RaytracedChannel channel(scene);
  Endpoint a, t1, t2;
  a.pose.position = Vec3(0, 0, 1);
  t1.pose.position = Vec3(3, 0, 1.5);
  t2.pose.position = Vec3(-4, 2, 1);
  const size_t expected = channel.paths(a, t1, 865.7e6).size() + channel.paths(a, t2, 865.7e6).size();
  EXPECT_EQ(counts(r.output), std::make_pair(2, static_cast<int>(expected))) << r.output;
  std::ifstream in(out);
  std::stringstream page;
  page << in.rdbuf();
  EXPECT_EQ(page.str().rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(page.str().find("REVISION=\"111\""), std::string::npos) << "three.js is inlined";
  EXPECT_NE(page.str().find("OrbitControls"), std::string::npos);
  std::filesystem::remove(out);
}

TEST(ViewCli, ScenarioAntennasAndTagsByName) {
  if (!std::filesystem::exists(kThree)) GTEST_SKIP() << "libjs-three not installed";
  const auto out = scratch("paper.html");
  const auto r = testing::run_rfidray("view " + kSource + "/scenes/paper_warehouse.yaml --antenna fixed --tag tag3 "
                                      "--tag tag8 --time 5 -o " + out.string());
  ASSERT_EQ(r.status, 0) << r.output;
  EXPECT_EQ(counts(r.output).first, 2) << r.output;
  EXPECT_GE(counts(r.output).second, 2) << r.output;
  EXPECT_NE(r.output.find("(single-bounce)"), std::string::npos) << r.output;
  std::filesystem::remove(out);
}

// --level is kept as an alias of --channel, and --help says so.
TEST(ViewCli, LevelIsAnAliasOfChannel) {
  if (!std::filesystem::exists(kThree)) GTEST_SKIP() << "libjs-three not installed";
  const std::string gw = " --scene " + kSource + "/scenes/ground_wall.obj --antenna 0,0,1 --tag 3,0,1.5 -o ";
  const auto out = scratch("alias.html");
  const auto level = testing::run_rfidray("view --level los" + gw + out.string());
  ASSERT_EQ(level.status, 0) << level.output;
  EXPECT_NE(level.output.find("(los)"), std::string::npos) << level.output;
  const auto channel = testing::run_rfidray("view --channel los" + gw + out.string());
  ASSERT_EQ(channel.status, 0) << channel.output;
  EXPECT_EQ(counts(level.output), counts(channel.output));
  std::filesystem::remove(out);
  const auto help = testing::run_rfidray("view --help");
  EXPECT_NE(help.output.find("--channel,--level"), std::string::npos) << help.output;
  EXPECT_NE(help.output.find("--level is an alias of --channel"), std::string::npos) << help.output;
}

TEST(ViewCli, BadInputExits2NamingTheOption) {
  const std::string paper = kSource + "/scenes/paper_warehouse.yaml";
  const std::string gw = kSource + "/scenes/ground_wall.obj";
  const auto out = scratch("bad.html");
  struct Case {
    std::string args, message;
  } cases[] = {
      {"view --scene " + gw + " --antenna 1,2 --tag 3,0,1", "option --antenna '1,2': field 'position': needs 3 numbers (got 2)"},
      {"view --scene " + gw + " --antenna 0,0,1 --tag 3,x,1", "option --tag '3,x,1': field 'position[1]': must be a number (got 'x')"},
      {"view --scene " + gw + " --antenna 0,0,1", "--scene: give --antenna X,Y,Z and --tag X,Y,Z"},
      {"view " + paper + " --antenna nope", "option --antenna: no 'nope' (known: mobile, fixed)"},
      {"view " + paper + " --time 1 --tick 3", "give --time or --tick, not both"},
      {"view --antenna 0,0,1", "give one of SCENARIO, --scene FILE.obj or --world FILE"},
      {"view " + paper + " --channel multi-bounce", "field '--channel': unknown channel 'multi-bounce'"},
      {"view " + paper + " --level multi-bounce", "field '--channel': unknown channel 'multi-bounce'"},  // the alias
      {"view " + paper + " -o /dev/null", "/dev/null: refusing to write view HTML: it exists and is not a regular file"},
  };
  for (const Case& c : cases) {
    const auto r = testing::run_rfidray(c.args + (c.args.find(" -o ") == std::string::npos ? " -o " + out.string() : ""));
    EXPECT_EQ(r.status, 2) << c.args << "\n" << r.output;
    EXPECT_NE(r.output.find(c.message), std::string::npos) << c.args << "\n" << r.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << c.args;
  }
}

}  // namespace
}  // namespace rfidray
