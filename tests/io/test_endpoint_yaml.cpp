// Endpoints and channel options from maps built in code (the Python API, `rfidray view`): the scenario
// reader's checks, with messages that start with the caller's `where`.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/units.h"
#include "io/scenario_yaml.h"
#include "tests/support/input_error.h"

namespace rfidray {
namespace {

YAML::Node map_of(const std::string& flow) { return YAML::Load(flow); }

std::string error_of(const std::function<void()>& f) { return testing::input_error_of(f); }

TEST(EndpointYaml, DefaultsAreThoseOfLink) {
  const Endpoint e = io::parse_endpoint(map_of("{position: [1, 2, 3]}"), "here", "");
  EXPECT_EQ(e.pose.position, Vec3(1, 2, 3));
  EXPECT_TRUE(e.pose.orientation.isApprox(Quat::Identity()));
  EXPECT_EQ(e.pattern.kind, PatternKind::kIsotropic);
  EXPECT_EQ(e.pattern.peak_gain_dbi, 0.0);
  EXPECT_EQ(e.polarization.kind, PolarizationKind::kLinear);
  EXPECT_EQ(e.polarization.axis_local, Vec3::UnitZ());
}

TEST(EndpointYaml, ScenarioKeys) {
  const Endpoint e = io::parse_endpoint(
      map_of("{position: [0, 0, 1], yaw_deg: 90, pattern: {kind: patch, gain_dbi: 8}, polarization: {kind: linear, axis: [0, 1, 0]}}"),
      "here", "");
  EXPECT_TRUE((e.pose.orientation * Vec3::UnitX()).isApprox(Vec3::UnitY(), 1e-15));
  EXPECT_EQ(e.pattern.kind, PatternKind::kPatch);
  EXPECT_EQ(e.pattern.peak_gain_dbi, 8.0);
  EXPECT_EQ(e.polarization.axis_local, Vec3::UnitY());
}

TEST(EndpointYaml, ErrorsNameWhereAndField) {
  EXPECT_EQ(error_of([] { io::parse_endpoint(map_of("{rpy_deg: [0, 0, 0]}"), "Endpoint", ""); }),
            "Endpoint: field 'position': is required");
  EXPECT_EQ(error_of([] { io::parse_endpoint(map_of("{position: [0, 0, 1e9]}"), "Endpoint", ""); }),
            "Endpoint: field 'position': must be within ±1e+08 (got 1e+09)");
  EXPECT_EQ(error_of([] { io::parse_endpoint(map_of("{position: [0, 0, 1], gain_dbi: 1000}"), "Endpoint", ""); }),
            error_of([] { io::parse_endpoint(map_of("{position: [0, 0, 1], pattern: {kind: isotropic, gain_dbi: 1000}}"), "Endpoint", ""); }));
  EXPECT_NE(error_of([] { io::parse_endpoint(map_of("{position: [0, 0, 1], polarisation: rhcp}"), "Endpoint", ""); })
                .find("Endpoint: field 'polarisation': unknown key 'polarisation' (did you mean 'polarization'?)"),
            std::string::npos);
}

TEST(ChannelOptionsYaml, ReadLikeAScenariosChannelOptions) {
  const ChannelOptionsSpec c = io::parse_channel_options(map_of("{candidates: exhaustive, drop_below_db: 30}"), "Channel");
  EXPECT_EQ(c.candidates, "exhaustive");
  EXPECT_EQ(c.drop_below_db, 30.0);
  EXPECT_EQ(error_of([] { io::parse_channel_options(map_of("{candidate_rays: -1}"), "Channel"); }),
            "Channel: field 'channel_options.candidate_rays': must be in 0…10000000 (got -1)");
}

}  // namespace
}  // namespace rfidray
