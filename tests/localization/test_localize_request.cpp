// loc::LocalizeRequest: the one check of localize's options that `rfidray localize` and Python's rfidray.localize
// share; each bad value is an InputError naming the field as the front end calls it, and a good request becomes
// the options every tag is localized with.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

#include "core/error.h"
#include "localization/localize_request.h"
#include "tests/support/input_error.h"

namespace rfidray::loc {
namespace {

LocalizeFieldNames names_with_prefix(const std::string& p) {
  const char* fields[] = {"method", "mirror_prior", "mirror_prior=truth", "frequency_hz", "max_range_m", "stride_m",
                          "max_residual_rad", "max_uncertainty_m", "systematic_phase_rad", "height_known", "truth",
                          "scenario", "channel", "tag_spacing_m", "antenna_file"};
  std::string name[15];
  for (int i = 0; i < 15; ++i) name[i] = p + fields[i];
  return {name[0], name[1], name[2],  name[3],  name[4],  name[5],  name[6], name[7],
          name[8], name[9], name[10], name[11], name[12], name[13], name[14]};
}

std::string error_of(const LocalizeRequest& r, const LocalizeFieldNames& n) {
  return testing::input_error_of([&] { validate(r, n); });
}

TEST(LocalizeRequest, EachBadFieldIsNamedAsTheFrontEndCallsIt) {
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  struct Case {
    std::function<void(LocalizeRequest&)> spoil;
    std::string message;  // with the field name "X.<field>"
  } cases[] = {
      {[](LocalizeRequest& r) { r.method = "magic"; }, "field 'X.method': must be hyperbolic, nlls, sar or all (got 'magic')"},
      {[](LocalizeRequest& r) { r.mirror_prior = "left"; }, "field 'X.mirror_prior': must be none, boresight or truth (got 'left')"},
      {[&](LocalizeRequest& r) { r.frequency_hz = nan; }, "field 'X.frequency_hz': must be a finite number > 0 (got nan)"},
      {[&](LocalizeRequest& r) { r.max_range_m = inf; }, "field 'X.max_range_m': must be a finite number > 0 (got inf)"},
      {[](LocalizeRequest& r) { r.max_range_m = 1e308; },
       "field 'X.max_range_m': must be at most 1e+08 m, the coordinate range (got 1e+308)"},
      {[](LocalizeRequest& r) { r.stride_m = 0.0; }, "field 'X.stride_m': must be a finite number > 0 (got 0)"},
      {[](LocalizeRequest& r) { r.max_residual_rad = -1.0; }, "field 'X.max_residual_rad': must be a finite number > 0 (got -1)"},
      {[](LocalizeRequest& r) { r.max_uncertainty_m = 0.0; }, "field 'X.max_uncertainty_m': must be a finite number > 0 (got 0)"},
      {[](LocalizeRequest& r) { r.systematic_phase_rad = -0.5; }, "field 'X.systematic_phase_rad': must be a finite number >= 0 (got -0.5)"},
      {[](LocalizeRequest& r) { r.has_channel = true; }, "field 'X.channel': needs X.scenario"},
      {[](LocalizeRequest& r) { r.height_known = true; }, "field 'X.height_known': needs X.truth (the tag z comes from it)"},
      {[](LocalizeRequest& r) { r.mirror_prior = "truth"; }, "field 'X.mirror_prior=truth': needs X.truth"},
      {[](LocalizeRequest& r) { r.tag_spacing_m = 0.08; },
       "field 'X.tag_spacing_m': needs X.antenna_file (it picks that file's allowance for the spacing)"},
      {[&](LocalizeRequest& r) { r.has_antenna_file = true, r.tag_spacing_m = nan; },
       "field 'X.tag_spacing_m': must be a finite number > 0 (got nan)"},
      {[](LocalizeRequest& r) { r.has_antenna_file = true, r.tag_spacing_m = 0.0; },
       "field 'X.tag_spacing_m': must be a finite number > 0 (got 0)"},
  };
  for (const Case& c : cases) {
    LocalizeRequest r;
    EXPECT_EQ(error_of(r, names_with_prefix("X.")), "");  // the defaults are valid
    c.spoil(r);
    EXPECT_EQ(error_of(r, names_with_prefix("X.")), c.message);
    EXPECT_NE(error_of(r, names_with_prefix("--")).find("'--"), std::string::npos);  // the other front end's name
  }
}

TEST(LocalizeRequest, PlanCarriesEveryOption) {
  LocalizeRequest r;
  r.method = "nlls";
  r.mirror_prior = "boresight";
  r.max_range_m = 3.0;
  r.stride_m = 0.2;
  r.max_residual_rad = 0.3;
  r.max_uncertainty_m = 0.1;
  r.fold_pi = true;
  const LocalizePlan plan = validate(r, names_with_prefix(""));
  ASSERT_EQ(plan.methods.size(), 1u);
  EXPECT_EQ(plan.methods[0], Method::kNlls);
  EXPECT_EQ(plan.options.mirror_prior, MirrorPrior::kBoresight);
  EXPECT_EQ(plan.options.max_range_m, 3.0);
  EXPECT_EQ(plan.options.stride_m, 0.2);
  EXPECT_EQ(plan.options.max_residual_rad, 0.3);
  EXPECT_EQ(plan.options.max_uncertainty_m, 0.1);
  EXPECT_TRUE(plan.options.fold_pi);
  EXPECT_FALSE(plan.needs_truth_per_tag);
  // The systematic allowance: the user's, else 0.1 rad with an antenna file and 0.2 without.
  // allowance_source says which, naming the user's field as the front end calls it.
  EXPECT_EQ(plan.options.systematic_phase_rad, 0.2);
  EXPECT_EQ(plan.allowance_source, "the default without an antenna file (0.2 rad)");
  r.has_antenna_file = true;
  EXPECT_EQ(validate(r, names_with_prefix("")).options.systematic_phase_rad, 0.1);
  EXPECT_EQ(validate(r, names_with_prefix("")).allowance_source, "the default with an antenna file (0.1 rad)");
  // A file without a measured allowance keeps the default, and a spacing given for it says it found none.
  r.tag_spacing_m = 0.08;
  LocalizePlan unmeasured = validate(r, names_with_prefix(""));
  unmeasured.options.calibration = AntennaCalibration{};
  apply_calibration_allowance(unmeasured, r);
  EXPECT_EQ(unmeasured.options.systematic_phase_rad, 0.1);
  EXPECT_NE(unmeasured.allowance_source.find("measured no allowance"), std::string::npos) << unmeasured.allowance_source;
  r.systematic_phase_rad = 0.0;
  EXPECT_EQ(validate(r, names_with_prefix("")).options.systematic_phase_rad, 0.0);
  EXPECT_EQ(validate(r, names_with_prefix("P.")).allowance_source, "P.systematic_phase_rad (0 rad)");
  r.tag_spacing_m.reset();
  r.method = "all";
  EXPECT_EQ(validate(r, names_with_prefix("")).methods,
            (std::vector<Method>{Method::kHyperbolic, Method::kNlls, Method::kSar}));
}

TEST(LocalizeRequest, TagOptionsTakeTheTruthAndTheSceneAllowance) {
  LocalizeRequest r;
  r.height_known = true;
  r.mirror_prior = "truth";
  r.has_truth = true;
  const LocalizeFieldNames n = names_with_prefix("");
  const LocalizePlan plan = validate(r, n);
  EXPECT_TRUE(plan.needs_truth_per_tag);
  const std::map<std::string, Vec3> truth{{"t1", Vec3(1, 2, 1.5)}};
  const LocalizeOptions o = tag_options(plan, "t1", truth, "tags.csv", n, [](const Vec3& p) { return p.x(); });
  EXPECT_TRUE(o.height_known);
  EXPECT_EQ(o.tag_height_m, 1.5);
  EXPECT_EQ(o.prior_point, Vec3(1, 2, 1.5));
  EXPECT_EQ(o.mirror_prior, MirrorPrior::kPoint);
  ASSERT_TRUE(o.multipath_phase_rad);
  EXPECT_EQ(o.multipath_phase_rad(Vec3(0.25, 0, 0)), 0.25);
  try {
    tag_options(plan, "t2", truth, "tags.csv", n);
    ADD_FAILURE() << "no error for a tag without truth";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "tags.csv: no ground truth for tag 't2' (needed by height_known / mirror_prior=truth)");
  }
  // Without height_known or the truth prior, a tag needs no truth.
  const LocalizePlan free = validate(LocalizeRequest{}, n);
  EXPECT_FALSE(tag_options(free, "t2", {}, "", n).multipath_phase_rad);
}

}  // namespace
}  // namespace rfidray::loc
