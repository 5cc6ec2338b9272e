// Each method on noise-free synthetic histories (φ = 4πD/λ + φ0 mod 2π from geometry), and each failure
// status on data built to trigger it.
#include <gtest/gtest.h>

#include <cmath>

#include "localization/methods.h"
#include "localization/synthetic.h"
#include "core/units.h"

namespace rfidray::loc {
namespace {

const double kLambda = wavelength_m(865.7e6);

// L-shaped path at 1.68 m like the paper's robot, 0.35 m/s, 15 Hz (2.3 cm per read, < λ/4 = 8.7 cm).
std::vector<PathSample> l_path() {
  return sample_polyline({Vec3(-1, -3, 1.68), Vec3(-1, 3, 1.68), Vec3(2, 3, 1.68)}, 0.35, 15.0);
}
// Non-planar path: the antenna also moves in Z (paper Fig. 11).
std::vector<PathSample> z_path() {
  return sample_polyline({Vec3(-1, -3, 0.6), Vec3(-1, 0, 2.1), Vec3(-1, 3, 0.6), Vec3(2, 3, 1.4)}, 0.35, 15.0);
}
std::vector<PathSample> straight_path(double length_m, double speed = 0.35) {
  return sample_polyline({Vec3(-1, -length_m / 2, 1.68), Vec3(-1, length_m / 2, 1.68)}, speed, 15.0);
}

const Vec3 kTag(1.5, 0.5, 2.05);

LocalizeOptions options_2d() {
  LocalizeOptions o;
  o.height_known = true;
  o.tag_height_m = kTag.z();
  return o;
}

SyntheticSpec clean_spec() {
  SyntheticSpec s;
  s.phase_offsets_rad = {1.234};
  return s;
}

class EachMethod : public ::testing::TestWithParam<Method> {};

TEST_P(EachMethod, RecoversTagIn2dNoiseFree) {
  const TagReads reads = synthesize("t", kTag, l_path(), clean_spec());
  const LocalizeResult r = localize(GetParam(), reads, options_2d());
  ASSERT_TRUE(r.ok) << to_string(r.reason) << ": " << r.detail;
  EXPECT_LT((r.position - kTag).norm(), 0.005);
  EXPECT_DOUBLE_EQ(r.position.z(), kTag.z());
}

TEST_P(EachMethod, RecoversTagIn3dWhenAntennaMovesInZ) {
  const TagReads reads = synthesize("t", kTag, z_path(), clean_spec());
  LocalizeOptions o;
  o.max_range_m = 6.0;
  const LocalizeResult r = localize(GetParam(), reads, o);
  ASSERT_TRUE(r.ok) << to_string(r.reason) << ": " << r.detail;
  EXPECT_LT((r.position - kTag).norm(), 0.005);
}

TEST_P(EachMethod, HandlesChannelHoppingWithDifferentOffsets) {
  SyntheticSpec s = clean_spec();
  s.frequencies_hz = {865.7e6, 866.3e6, 866.9e6, 867.5e6};
  s.phase_offsets_rad = {0.3, 2.0, 4.1, 5.5};
  s.hop_dwell_s = 2.0;  // 0.7 m per dwell
  const TagReads reads = synthesize("t", kTag, l_path(), s);
  ASSERT_EQ(reads.groups.size(), 4u);
  const LocalizeResult r = localize(GetParam(), reads, options_2d());
  ASSERT_TRUE(r.ok) << to_string(r.reason) << ": " << r.detail;
  EXPECT_LT((r.position - kTag).norm(), 0.005);
}

TEST_P(EachMethod, SignedPhaseGivesSameEstimate) {
  SyntheticSpec s = clean_spec();
  const LocalizeResult a = localize(GetParam(), synthesize("t", kTag, l_path(), s), options_2d());
  s.signed_phase = true;
  const LocalizeResult b = localize(GetParam(), synthesize("t", kTag, l_path(), s), options_2d());
  ASSERT_TRUE(a.ok && b.ok);
  EXPECT_LT((a.position - b.position).norm(), 1e-6);
}

TEST_P(EachMethod, TooShortApertureFails) {
  const TagReads reads = synthesize("t", kTag, straight_path(0.2, 0.1), clean_spec());
  ASSERT_GE(reads.read_count(), 8u);
  const LocalizeResult r = localize(GetParam(), reads, options_2d());
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.reason, FailReason::kApertureTooShort) << r.detail;
}

TEST_P(EachMethod, ShortPathFarTagFailsOnApertureAngle) {
  // 0.6 m of path (above min_aperture_m) seen from 6 m: ~6 deg < 10 deg.
  const Vec3 far_tag(5.0, 0.0, 2.05);
  LocalizeOptions o = options_2d();
  o.mirror_prior = MirrorPrior::kPoint;  // isolate the aperture test from the (also present) mirror ambiguity
  o.prior_point = far_tag;
  const LocalizeResult r = localize(GetParam(), synthesize("t", far_tag, straight_path(0.6), clean_spec()), o);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.reason, FailReason::kApertureTooShort) << r.detail;
}

TEST_P(EachMethod, TooFewReadsFails) {
  std::vector<PathSample> p = l_path();
  p.resize(6);
  const LocalizeResult r = localize(GetParam(), synthesize("t", kTag, p, clean_spec()), options_2d());
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.reason, FailReason::kTooFewReads);
  EXPECT_EQ(r.status(), Status::kFailed);
}

TEST_P(EachMethod, TwoReadsAreFailedWithoutAPosition) {
  std::vector<PathSample> p = l_path();
  p.resize(2);
  const LocalizeResult r = localize(GetParam(), synthesize("t", kTag, p, clean_spec()), options_2d());
  EXPECT_EQ(r.status(), Status::kFailed);
  EXPECT_EQ(r.reason, FailReason::kTooFewReads) << r.detail;
  EXPECT_FALSE(r.position.allFinite());
  EXPECT_TRUE(std::isnan(r.uncertainty_m));
  EXPECT_STREQ(to_string(r.status()), "failed");
}

// A radius above the user's limit is reported, with the position, as uncertain — not thrown away.
TEST_P(EachMethod, RadiusAboveTheLimitIsUncertainWithItsPosition) {
  SyntheticSpec s = clean_spec();
  s.phase_noise_rad = 0.1;
  const TagReads reads = synthesize("t", kTag, l_path(), s);
  const LocalizeResult ok = localize(GetParam(), reads, options_2d());
  ASSERT_TRUE(ok.ok) << to_string(ok.reason) << ": " << ok.detail;
  LocalizeOptions tight = options_2d();
  tight.max_uncertainty_m = ok.uncertainty_m / 2.0;
  const LocalizeResult r = localize(GetParam(), reads, tight);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.status(), Status::kUncertain) << to_string(r.reason) << ": " << r.detail;
  EXPECT_STREQ(to_string(r.status()), "uncertain");
  ASSERT_TRUE(r.position.allFinite());
  EXPECT_GT(r.uncertainty_m, tight.max_uncertainty_m);
  EXPECT_NE(r.detail.find("position uncertainty"), std::string::npos) << r.detail;
  // The same fit as the ok one: the gate changes the status, not the answer.
  EXPECT_LT((r.position - ok.position).norm(), 1e-9);
  EXPECT_DOUBLE_EQ(r.uncertainty_m, ok.uncertainty_m);
}

// A 95 % region wider than the search region places the tag nowhere the search region did not: failed, no
// position (not a point with a radius of kilometres, as some real AdaRF fits had).
TEST_P(EachMethod, RadiusWiderThanTheSearchRegionIsFailedWithoutAPosition) {
  const Vec3 tag(0.5, 0.0, 2.05);  // 1.5 m from a 0.8 m straight pass (x = −1): the range is poorly determined
  SyntheticSpec s = clean_spec();
  s.phase_noise_rad = 0.8;
  const TagReads reads = synthesize("t", tag, straight_path(0.8), s);
  LocalizeOptions o = options_2d();
  o.mirror_prior = MirrorPrior::kPoint;
  o.prior_point = tag;
  o.max_range_m = 6.0;
  const LocalizeResult wide = localize(GetParam(), reads, o);
  ASSERT_TRUE(wide.has_position()) << to_string(wide.reason) << ": " << wide.detail;
  // A search region that still holds the fit (its distance from the path + 10 cm) but is narrower than its radius.
  const double reach_m = std::hypot(wide.position.x() + 1.0, std::max(0.0, std::abs(wide.position.y()) - 0.4)) + 0.1;
  ASSERT_LT(reach_m, wide.uncertainty_m);
  o.max_range_m = reach_m;
  const LocalizeResult r = localize(GetParam(), reads, o);
  EXPECT_EQ(r.status(), Status::kFailed) << to_string(r.reason) << ": " << r.detail;
  EXPECT_EQ(r.reason, FailReason::kNotLocated) << r.detail;
  EXPECT_FALSE(r.position.allFinite());
  EXPECT_NE(r.detail.find("wider than the search region"), std::string::npos) << r.detail;
  // The same reads with the region as wide as the radius: the position is given again.
  o.max_range_m = wide.uncertainty_m * 1.01;
  EXPECT_TRUE(localize(GetParam(), reads, o).has_position());
}

TEST_P(EachMethod, StraightPathIsAmbiguousMirror) {
  const TagReads reads = synthesize("t", kTag, straight_path(6.0), clean_spec());
  const LocalizeResult r = localize(GetParam(), reads, options_2d());
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.reason, FailReason::kAmbiguousMirror) << r.detail;
  // Two positions fit equally: neither is reported.
  EXPECT_EQ(r.status(), Status::kFailed);
  EXPECT_FALSE(r.position.allFinite());
}

TEST_P(EachMethod, StraightPathMirrorSettledByPriors) {
  const TagReads reads = synthesize("t", kTag, straight_path(6.0), clean_spec());
  LocalizeOptions o = options_2d();
  o.mirror_prior = MirrorPrior::kPoint;
  o.prior_point = Vec3(3.0, 0.0, 2.05);  // only which side: far from the tag itself
  LocalizeResult r = localize(GetParam(), reads, o);
  ASSERT_TRUE(r.ok) << r.detail;
  EXPECT_EQ(r.mirror_resolved_by, "prior_point");
  EXPECT_LT((r.position - kTag).norm(), 0.005);
  // Boresight: the path runs along +Y and the tag is at +X, i.e. to the right: yaw −π/2.
  const TagReads right = synthesize("t", kTag, sample_polyline({Vec3(-1, -3, 1.68), Vec3(-1, 3, 1.68)}, 0.35, 15.0, -kPi / 2), clean_spec());
  o.mirror_prior = MirrorPrior::kBoresight;
  r = localize(GetParam(), right, o);
  ASSERT_TRUE(r.ok) << r.detail;
  EXPECT_EQ(r.mirror_resolved_by, "boresight");
  EXPECT_LT((r.position - kTag).norm(), 0.005);
}

TEST_P(EachMethod, StraightPathIn3dIsAmbiguous) {
  LocalizeOptions o;
  o.max_range_m = 6.0;
  const LocalizeResult r = localize(GetParam(), synthesize("t", kTag, straight_path(6.0), clean_spec()), o);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.reason, FailReason::kAmbiguousMirror) << r.detail;
}

INSTANTIATE_TEST_SUITE_P(Localization, EachMethod,
                         ::testing::Values(Method::kHyperbolic, Method::kNlls, Method::kSar),
                         [](const auto& info) { return std::string(to_string(info.param)); });

TEST(Undersampling, UnwrappingMethodsFailAboveQuarterWavelength) {
  // 15 Hz at 1.8 m/s: 0.12 m per read > λ/4.
  const std::vector<PathSample> fast =
      sample_polyline({Vec3(-1, -3, 1.68), Vec3(-1, 3, 1.68), Vec3(2, 3, 1.68)}, 1.8, 15.0);
  ASSERT_GT((fast[1].position - fast[0].position).norm(), kLambda / 4);
  const TagReads reads = synthesize("t", kTag, fast, clean_spec());
  for (Method m : {Method::kHyperbolic, Method::kNlls}) {
    const LocalizeResult r = localize(m, reads, options_2d());
    EXPECT_FALSE(r.ok) << to_string(m);
    EXPECT_EQ(r.reason, FailReason::kUndersampled) << to_string(m) << ": " << r.detail;
  }
  // SAR does not unwrap: it may still focus, but never silently on a wrong point.
  const LocalizeResult sar = localize(Method::kSar, reads, options_2d());
  if (sar.ok) EXPECT_LT((sar.position - kTag).norm(), 0.005);
  else EXPECT_EQ(sar.reason, FailReason::kUndersampled) << sar.detail;
}

TEST(QualityGates, UnwrappingMethodsFailOnCycleSlipsInsteadOfReturningAWrongPoint) {
  // σφ = 1 rad: the unwrapped history slips cycles; the fit would be centimetres to decimetres off.
  SyntheticSpec s = clean_spec();
  s.phase_noise_rad = 1.0;
  for (uint64_t trial = 0; trial < 3; ++trial) {
    s.stream = trial;
    const TagReads reads = synthesize("t", kTag, l_path(), s);
    for (Method m : {Method::kHyperbolic, Method::kNlls}) {
      const LocalizeResult r = localize(m, reads, options_2d());
      EXPECT_FALSE(r.ok) << to_string(m) << " error " << (r.position - kTag).norm();
      // The joint fit on the wrapped phase (no unwrapping) goes on from the slipped estimate: with a position
      // it is uncertain, reason phase too noisy, and its radius holds the truth; or it finds other optima that
      // fit as well and gives none.
      if (r.status() == Status::kUncertain) {
        EXPECT_EQ(r.reason, FailReason::kNoisyPhase) << to_string(m) << ": " << r.detail;
        EXPECT_LE((r.position - kTag).norm(), r.uncertainty_m) << to_string(m) << ": " << r.detail;
      } else {
        EXPECT_TRUE(r.reason == FailReason::kAmbiguousMirror || r.reason == FailReason::kAmbiguousPeak ||
                    r.reason == FailReason::kNoisyPhase)
            << to_string(m) << ": " << r.detail;
        EXPECT_FALSE(r.position.allFinite()) << to_string(m);
      }
    }
  }
}

TEST(QualityGates, WeakGeometryFailsOnPredictedUncertainty) {
  // 1 m of L-shaped path (aperture angle above the 10° pre-check) with σφ = 0.1 rad: decimetre-level
  // uncertainty, reported as aperture too short rather than as an ok estimate.
  SyntheticSpec s = clean_spec();
  s.phase_noise_rad = 0.1;
  const auto path = sample_polyline({Vec3(-1, 0.2, 1.68), Vec3(-1, 0.87, 1.68), Vec3(-0.67, 0.87, 1.68)}, 0.35, 15.0);
  const LocalizeResult r = localize_nlls(synthesize("t", kTag, path, s), options_2d());
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.reason, FailReason::kApertureTooShort) << r.detail;
  EXPECT_GT(r.predicted_std_m, options_2d().max_std_m);
  // Uncertain, not failed: the position and a radius that holds the truth.
  ASSERT_EQ(r.status(), Status::kUncertain) << r.detail;
  EXPECT_LE((r.position - kTag).norm(), r.uncertainty_m);
}

TEST(QualityGates, PaperNoiseLevelPassesWithSmallPredictedUncertainty) {
  SyntheticSpec s = clean_spec();
  s.phase_noise_rad = 0.1;
  const LocalizeResult r = localize_nlls(synthesize("t", kTag, l_path(), s), options_2d());
  ASSERT_TRUE(r.ok) << r.detail;
  EXPECT_LT(r.predicted_std_m, 0.005);
  // The predicted 1-σ is honest: the actual error is within a few σ.
  EXPECT_LT((r.position - kTag).norm(), 4 * r.predicted_std_m + 1e-4);
}

TEST(Nlls, StartsFromGivenInitialGuess) {
  const TagReads reads = synthesize("t", kTag, l_path(), clean_spec());
  const Vec3 guess = kTag + Vec3(0.3, -0.2, 0.0);
  const LocalizeResult r = localize_nlls(reads, options_2d(), &guess);
  ASSERT_TRUE(r.ok) << r.detail;
  EXPECT_LT((r.position - kTag).norm(), 1e-4);
  EXPECT_LT(r.rms_residual_m, 1e-6);
}

}  // namespace
}  // namespace rfidray::loc
