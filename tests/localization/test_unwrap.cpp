// Phase unwrapping on synthetic histories: exact below λ/4 per read, split (not a wrong cycle) above.
#include <gtest/gtest.h>

#include <cmath>

#include "localization/phase_unwrap.h"
#include "localization/synthetic.h"
#include "core/units.h"

namespace rfidray::loc {
namespace {

const double kF = 865.7e6;
const double kLambda = wavelength_m(kF);

UnwrapOptions opts() {
  UnwrapOptions o;
  o.frequency_hz = kF;
  return o;
}

// Antenna driving straight at the tag: ΔD = step, the hardest case for unwrapping.
std::vector<PhaseRead> radial_history(double step_m, int n, double phi0 = 2.5) {
  const Vec3 tag(10.0, 0.0, 0.0);
  std::vector<PhaseRead> out;
  for (int k = 0; k < n; ++k) {
    const Vec3 p(k * step_m, 0.0, 0.0);
    out.push_back({0.05 * k, p, Quat::Identity(), wrap_to_2pi(phi0 + 4 * kPi * (tag - p).norm() / kLambda)});
  }
  return out;
}

TEST(Unwrap, PlainSequenceRecoversRamp) {
  std::vector<double> wrapped, truth;
  for (int k = 0; k < 200; ++k) {
    truth.push_back(0.3 + 2.9 * k);  // steps of 2.9 rad < π
    wrapped.push_back(wrap_to_2pi(truth.back()));
  }
  const std::vector<double> u = unwrap(wrapped);
  for (size_t k = 0; k < u.size(); ++k) EXPECT_NEAR(u[k] - u[0], truth[k] - truth[0], 1e-9);
}

TEST(Unwrap, ExactBelowQuarterWavelengthPerRead) {
  for (double fraction : {0.05, 0.15, 0.24}) {
    const auto h = radial_history(fraction * kLambda, 120);
    const UnwrapResult r = unwrap_history(h, opts());
    ASSERT_EQ(r.segments.size(), 1u) << fraction;
    EXPECT_EQ(r.splits(), 0);
    const auto& s = r.segments[0];
    for (size_t k = 0; k < s.index.size(); ++k) {
      // Range decreases by one step per read: phase by 4π·step/λ.
      const double expected = -4 * kPi * fraction * kLambda * static_cast<double>(k) / kLambda;
      EXPECT_NEAR(s.unwrapped_rad[k] - s.unwrapped_rad[0], expected, 1e-9) << fraction << " k=" << k;
    }
  }
}

TEST(Unwrap, SplitsAboveQuarterWavelengthInsteadOfAddingWrongCycle) {
  // 0.3 λ per read: the wrapped change is 1.2π → looks like −0.8π. Plain unwrapping gets the sign wrong.
  const auto h = radial_history(0.3 * kLambda, 20);
  std::vector<double> phase;
  for (const auto& r : h) phase.push_back(r.phase_rad);
  const std::vector<double> naive = unwrap(phase);
  EXPECT_GT(naive[1] - naive[0], 0.0);  // wrong direction: this is the silent error we must avoid
  const UnwrapResult r = unwrap_history(h, opts());
  EXPECT_EQ(r.splits_step, 19);
  EXPECT_EQ(r.segments.size(), 20u);
  for (const auto& s : r.segments) EXPECT_EQ(s.index.size(), 1u);
}

TEST(Unwrap, SplitsAtTimeGap) {
  auto h = radial_history(0.1 * kLambda, 40);
  for (size_t k = 20; k < h.size(); ++k) h[k].time_s += 5.0;
  const UnwrapResult r = unwrap_history(h, opts());
  EXPECT_EQ(r.splits_gap, 1);
  ASSERT_EQ(r.segments.size(), 2u);
  EXPECT_EQ(r.segments[1].index.front(), 20);
}

TEST(Unwrap, SplitsAtPhysicallyImpossibleJump) {
  // Antenna creeping 1 mm per read (0.036 rad of phase at most), one read jumps by 2 rad.
  auto h = radial_history(0.001, 40);
  h[25].phase_rad = wrap_to_2pi(h[25].phase_rad + 2.0);
  const UnwrapResult r = unwrap_history(h, opts());
  EXPECT_EQ(r.splits_jump, 2);  // into and out of the outlier
  EXPECT_EQ(r.splits_step, 0);
}

TEST(Unwrap, SignedAndUnsignedPhaseAgree) {
  auto h = radial_history(0.2 * kLambda, 50);
  auto signed_h = h;
  for (auto& r : signed_h) r.phase_rad = wrap_to_pi(r.phase_rad);
  const UnwrapResult a = unwrap_history(h, opts()), b = unwrap_history(signed_h, opts());
  ASSERT_EQ(a.segments.size(), 1u);
  ASSERT_EQ(b.segments.size(), 1u);
  for (size_t k = 0; k < h.size(); ++k)
    EXPECT_NEAR(a.segments[0].unwrapped_rad[k] - a.segments[0].unwrapped_rad[0],
                b.segments[0].unwrapped_rad[k] - b.segments[0].unwrapped_rad[0], 1e-9);
}

TEST(Unwrap, HoppingChannelsStaySeparateHistories) {
  SyntheticSpec s;
  s.frequencies_hz = {865.7e6, 866.3e6, 866.9e6, 867.5e6};
  s.phase_offsets_rad = {0.0, 1.0, 2.0, 3.0};
  s.hop_dwell_s = 0.4;
  const auto path = sample_polyline({Vec3(0, 0, 0), Vec3(0, 4, 0)}, 0.35, 15.0);
  const TagReads t = synthesize("t", Vec3(2, 2, 1), path, s);
  ASSERT_EQ(t.groups.size(), 4u);
  for (const auto& g : t.groups) {
    UnwrapOptions o;
    o.frequency_hz = g.frequency_hz;
    const UnwrapResult r = unwrap_history(g.reads, o);
    // Between dwells on the same channel the antenna moves 3 × 0.4 s × 0.35 m/s = 0.42 m > λ/4: split.
    EXPECT_GT(r.splits_step, 0);
    EXPECT_EQ(r.splits_jump, 0);
    // Within a segment, exact relative range.
    for (const auto& seg : r.segments)
      for (size_t k = 0; k < seg.index.size(); ++k) {
        const double d0 = (Vec3(2, 2, 1) - g.reads[seg.index[0]].antenna_m).norm();
        const double dk = (Vec3(2, 2, 1) - g.reads[seg.index[k]].antenna_m).norm();
        EXPECT_NEAR((seg.unwrapped_rad[k] - seg.unwrapped_rad[0]) * wavelength_m(g.frequency_hz) / (4 * kPi), dk - d0, 1e-9);
      }
  }
}

}  // namespace
}  // namespace rfidray::loc
