// channel_errors: phase and RSSI errors of a test channel against a reference on what a reader reports, over
// the links readable in either; link samples for `channel: auto`.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "core/channel_error.h"
#include "core/link_sample.h"
#include "core/simulation.h"
#include "core/units.h"

namespace rfidray {
namespace {

using C = std::complex<double>;

TEST(ChannelError, PhaseIsTheRoundTripAndRssiIsFortyLogOfTheMagnitude) {
  // h·e^{jδ}: round-trip phase error 2δ; h·a: RSSI error 40·log10(a).
  const std::vector<C> ref{{1e-2, 0}, {0, 2e-2}, {-3e-2, 1e-2}, {5e-3, -5e-3}};
  std::vector<C> test(ref.size());
  const double delta = 0.01, a = 1.1;
  for (size_t i = 0; i < ref.size(); ++i) test[i] = ref[i] * (i < 2 ? std::polar(1.0, delta) : C(a, 0));
  const std::vector<double> min_h2(ref.size(), 1e-6);
  const ChannelErrorStats s = channel_errors(ref, test, min_h2);
  EXPECT_EQ(s.links, 4u);
  EXPECT_EQ(s.status_mismatches, 0u);
  EXPECT_NEAR(s.phase_max_rad, 2 * delta, 1e-12);
  EXPECT_NEAR(s.rssi_max_db, 40 * std::log10(a), 1e-9);
  EXPECT_NEAR(s.magnitude_p95, a - 1, 1e-12);
  EXPECT_NEAR(s.phase_p50_rad, 0.0, 1e-12);  // nearest rank: 2 of 4 values are 0
}

TEST(ChannelError, PhaseWrapsAndUnreadableLinksAreMismatchesOrIgnored) {
  const std::vector<C> ref{std::polar(1e-2, 1.5), {1e-2, 0}, {1e-5, 0}, {1e-5, 0}, {2e-2, 0}, {0, 2e-2}};
  // Link 0: arg h² goes 3.0 → −3.0 (6 rad apart, 0.283 wrapped). Link 1 unreadable in the test.
  // Link 2 readable in the test only. Link 3 unreadable in both: ignored. Links 4, 5 exact.
  // Sorted phase errors: 0, 0, 0.283, inf, inf → nearest-rank median 0.283.
  const std::vector<C> test{std::polar(1e-2, -1.5), {1e-5, 0}, {1e-2, 0}, {2e-5, 0}, {2e-2, 0}, {0, 2e-2}};
  const std::vector<double> min_h2(6, 1e-6);
  const ChannelErrorStats s = channel_errors(ref, test, min_h2);
  EXPECT_EQ(s.links, 5u);
  EXPECT_EQ(s.status_mismatches, 2u);
  EXPECT_NEAR(s.phase_p50_rad, kTwoPi - 6.0, 1e-12);
  EXPECT_TRUE(std::isinf(s.phase_p95_rad));
  EXPECT_TRUE(std::isinf(s.rssi_max_db));
  EXPECT_NEAR(s.phase_p95_both_rad, kTwoPi - 6.0, 1e-12);  // mismatches left out: 0, 0, 0.283
  EXPECT_THROW(channel_errors(ref, std::vector<C>(3), min_h2), std::invalid_argument);
}

TagSpec tag_at(const std::string& name, const Vec3& p, double start_s = 0.0) {
  TagSpec t;
  t.tag.name = name;
  t.motion.pose.position = p;
  t.start_s = start_s;
  return t;
}

TEST(LinkSample, StaticScenarioGivesOnePoseMovingOneSpreadsOverTheRun) {
  Scenario s;
  AntennaSpec fixed;
  fixed.reader.name = "fixed";
  fixed.motion.pose.position = Vec3(0, 0, 1);
  s.antennas.push_back(fixed);
  AntennaSpec mover;
  mover.reader.name = "mover";
  mover.reader.frequencies_hz = {865.7e6, 866.3e6};
  mover.reader.phase_offsets_rad = {0, 0};
  mover.motion.kind = MotionSpec::Kind::kWaypoints;
  mover.motion.waypoints = {Vec3(0, -5, 1), Vec3(0, 5, 1)};
  mover.motion.speed_m_s = 1.0;  // 10 s, 151 ticks at 15 Hz
  s.antennas.push_back(mover);
  s.tags = {tag_at("a", Vec3(2, 0, 1)), tag_at("b", Vec3(2, 1, 1)), tag_at("late", Vec3(2, 2, 1), 5.0)};
  const auto batches = sample_link_batches(s, build_motion(s), 60);  // 60 / (2 antennas × 3 tags) = 10 poses per antenna
  size_t fixed_poses = 0, mover_poses = 0;
  double last_t = -1.0;
  for (const LinkBatch& b : batches) {
    ASSERT_EQ(b.tags.size(), b.tag_ends.size());
    ASSERT_EQ(b.tags.size(), b.min_readable_h2.size());
    for (size_t k = 0; k < b.tags.size(); ++k) {
      EXPECT_GE(b.time_s, s.tags[b.tags[k]].start_s);  // only present tags
      EXPECT_EQ(b.tag_ends[k].pose.position, s.tags[b.tags[k]].motion.pose.position);
    }
    if (b.antenna == 0) {
      ++fixed_poses;
    } else {
      ++mover_poses;
      EXPECT_GT(b.time_s, last_t);
      last_t = b.time_s;
      EXPECT_NEAR(b.antenna_end.pose.position.y(), -5.0 + b.time_s, 1e-9);  // the pose at that time
    }
  }
  EXPECT_EQ(fixed_poses, 1u);  // antenna and tags static: one pose says it all
  EXPECT_EQ(mover_poses, 10u);
  EXPECT_GT(last_t, 9.0);  // spread over the whole run
  // The late tag is sampled only after it appears; the carrier follows the hop plan.
  size_t late = 0;
  for (const LinkBatch& b : batches) {
    for (size_t i : b.tags) late += i == 2;
    const ReaderParams& r = s.antennas[b.antenna].reader;
    EXPECT_EQ(b.frequency_hz, r.frequencies_hz[hop_index_at(r, b.time_s)]);
  }
  EXPECT_EQ(late, 5u);  // the mover's poses at t ≈ 5.5, 6.5, 7.5, 8.5, 9.5 s
}

}  // namespace
}  // namespace rfidray

namespace rfidray {
namespace {

TEST(LinkSample, ManyTagsAreSubsampledButCounted) {
  Scenario s;
  AntennaSpec a;
  a.reader.name = "a";
  a.motion.pose.position = Vec3(0, 0, 1);
  s.antennas.push_back(a);
  for (int i = 0; i < 5000; ++i) {
    TagSpec t;
    t.tag.name = "t" + std::to_string(i);
    t.motion.pose.position = Vec3(1.0 + 0.001 * i, 2.0, 1.0);
    s.tags.push_back(t);
  }
  s.duration_s = 1.0;
  const auto batches = sample_link_batches(s, build_motion(s), 1000);
  ASSERT_EQ(batches.size(), 1u);
  EXPECT_EQ(batches[0].tags_present, 5000u);
  EXPECT_EQ(batches[0].tags.size(), 1000u);  // every 5th
  EXPECT_EQ(batches[0].tags[1], 5u);
}

}  // namespace
}  // namespace rfidray
