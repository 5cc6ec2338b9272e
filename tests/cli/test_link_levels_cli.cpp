// `rfidray link --channel double-bounce | full --json`: the new path kinds with their interaction points and
// coefficients, equal to the library's.
#include <gtest/gtest.h>

#include "tests/support/run_rfidray.h"

#include <nlohmann/json.hpp>
#include <string>

#include "raytrace/raytraced_channel.h"

namespace rfidray {
namespace {

const std::string kScene = std::string(RFIDRAY_SOURCE_DIR) + "/scenes/paper_warehouse.obj";

TEST(LinkLevelsCli, DoubleBounceAndFullListTheNewPaths) {
  Endpoint ant, tag;
  ant.pose.position = Vec3(-1, -3, 0.6);
  tag.pose.position = Vec3(2.9, -2.35, 2.05);
  const auto scene = load_scene({kScene}, MaterialAssignment{});
  for (const auto& [level, kind] : {std::pair{ChannelLevel::kDoubleBounce, std::string("reflection2")},
                                    std::pair{ChannelLevel::kFull, std::string("diffraction")}}) {
    const auto r = rfidray::testing::run_rfidray("link --json --scene " + kScene + " --channel " + to_string(level) +
                                                 " --antenna=-1,-3,0.6 --tag 2.9,-2.35,2.05 --frequency 866e6");
    ASSERT_EQ(r.status, 0) << r.output;
    const nlohmann::json j = nlohmann::json::parse(r.output.substr(r.output.find('{')));
    EXPECT_EQ(j["level"], to_string(level));
    TraceOptions o;
    o.level = level;
    const auto paths = RaytracedChannel(scene, o).paths(ant, tag, 866e6);
    const auto& jp = j["raytraced"]["paths"];
    ASSERT_EQ(jp.size(), paths.size());
    size_t found = 0;
    for (size_t i = 0; i < paths.size(); ++i) {
      EXPECT_EQ(jp[i]["kind"], to_string(paths[i].kind));
      EXPECT_DOUBLE_EQ(jp[i]["coefficient"]["re"].get<double>(), paths[i].coefficient.real());
      EXPECT_DOUBLE_EQ(jp[i]["coefficient"]["im"].get<double>(), paths[i].coefficient.imag());
      if (jp[i]["kind"] != kind) continue;
      ++found;
      const size_t points = kind == "reflection2" ? 2u : 1u;
      ASSERT_EQ(jp[i]["points"].size(), points);
      for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(jp[i]["points"][0][k].get<double>(), paths[i].point[k]);
      if (points == 2) {
        for (int k = 0; k < 3; ++k) EXPECT_DOUBLE_EQ(jp[i]["points"][1][k].get<double>(), paths[i].point2[k]);
        EXPECT_EQ(jp[i]["material2"], paths[i].material2);
      }
    }
    EXPECT_GT(found, 0u) << "no " << kind << " path listed";
  }
}

}  // namespace
}  // namespace rfidray
