// The Cramér–Rao bound of a tag position from phase (localization/cramer_rao.h) against closed forms.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "core/units.h"
#include "localization/cramer_rao.h"

namespace rfidray::localization {
namespace {

// N reads from antennas evenly spaced on a circle around the tag (one carrier): the gradients 4π/λ·u_i are
// isotropic in the plane and sum to zero, so the offset decouples and J = (N/2)·k²/σ²·I (k = 4π/λ):
// CRB = 2·(2/N)·σ²/k², i.e. the RMS bound √(4σ²/(N k²)) = 2σ/(k√N).
TEST(CramerRao, CircleOfAntennasClosedForm) {
  const double lambda = 0.3463, sigma = 0.1;
  const Vec3 tag(1.0, 2.0, 1.5);
  for (int n : {8, 64}) {
    std::vector<PhaseObservation> obs;
    for (int i = 0; i < n; ++i) {
      const double a = kTwoPi * i / n;
      obs.push_back({tag + 2.0 * Vec3(std::cos(a), std::sin(a), 0.0), lambda, 0, 1.0, sigma});
    }
    const double k = 4.0 * kPi / lambda;
    const auto b = phase_position_crb_m(tag, obs, true);
    ASSERT_TRUE(b.has_value());
    EXPECT_NEAR(*b, 2.0 * sigma / (k * std::sqrt(double(n))), 1e-12);
    // Weights are expected read counts: reads at p = 0.25 count a quarter.
    for (auto& o : obs) o.weight = 0.25;
    EXPECT_NEAR(*phase_position_crb_m(tag, obs, true), 2.0 * 2.0 * sigma / (k * std::sqrt(double(n))), 1e-12);
  }
}

// A straight pass: with the height known the (x, y) position is identifiable; in 3-D the tag can rotate about
// the pass's axis (the mirror/cone ambiguity, locally a flat direction only when the tag is in the pass's
// plane); and with one read, nothing is.
TEST(CramerRao, StraightPassIdentifiability) {
  const double lambda = 0.3463;
  const Vec3 tag(1.0, 0.5, 0.0);
  std::vector<PhaseObservation> obs;
  for (int i = 0; i <= 40; ++i) obs.push_back({Vec3(0.0, -1.0 + 0.05 * i, 0.0), lambda, 0, 1.0, 0.1});
  const auto b2 = phase_position_crb_m(tag, obs, true);
  ASSERT_TRUE(b2.has_value());
  EXPECT_GT(*b2, 0.0);
  EXPECT_LT(*b2, 0.05);
  EXPECT_FALSE(phase_position_crb_m(tag, obs, false).has_value());
  EXPECT_FALSE(phase_position_crb_m(tag, std::vector<PhaseObservation>(obs.begin(), obs.begin() + 1), true));
  // A longer aperture constrains better; two carriers with their own offsets give more information than one.
  std::vector<PhaseObservation> longer;
  for (int i = 0; i <= 40; ++i) longer.push_back({Vec3(0.0, -2.0 + 0.1 * i, 0.0), lambda, 0, 1.0, 0.1});
  EXPECT_LT(*phase_position_crb_m(tag, longer, true), *b2);
  auto two = obs;
  for (auto o : obs) two.push_back({o.antenna_m, 0.3440, 1, 1.0, 0.1});
  EXPECT_LT(*phase_position_crb_m(tag, two, true), *b2);
}

// Two antennas with offsets of their own (groups 0 and 1) on different passes: the joint bound is that of the
// summed informations (what `place --objective worst-bound` uses), and it is below either antenna's alone. Two
// perpendicular straight passes, each weak across its own line, together constrain both directions.
TEST(CramerRao, InformationsOfAntennasAdd) {
  const double lambda = 0.3463;
  const Vec3 tag(0.3, 0.2, 0.0);
  PhaseFisher a(tag), b(tag), joint(tag);
  for (int i = 0; i <= 30; ++i) {
    const PhaseObservation oa{Vec3(-1.5 + 0.1 * i, -1.0, 0.5), lambda, 0, 0.8, 0.1};
    const PhaseObservation ob{Vec3(2.0, -1.5 + 0.1 * i, 0.5), lambda, 1, 0.6, 0.15};
    a.add(oa), b.add(ob), joint.add(oa), joint.add(ob);
  }
  const Eigen::Matrix3d sum = a.information() + b.information();
  EXPECT_TRUE(sum.isApprox(joint.information(), 1e-12));
  for (bool height_known : {true, false}) {
    const auto j = joint.bound_m(height_known), s = position_bound_m(sum, height_known);
    ASSERT_TRUE(j.has_value() && s.has_value());
    EXPECT_NEAR(*s, *j, 1e-12 * *j);
    for (const PhaseFisher* one : {&a, &b})
      if (auto alone = one->bound_m(height_known)) { EXPECT_LT(*j, *alone); }
  }
  // Packing keeps the matrix.
  EXPECT_EQ(unpack_information(pack_information(sum).data()), sum);
  // Not identifiable: no information, or a non-finite one.
  EXPECT_FALSE(position_bound_m(Eigen::Matrix3d::Zero(), true).has_value());
  Eigen::Matrix3d bad = sum;
  bad(0, 0) = std::nan("");
  EXPECT_FALSE(position_bound_m(bad, true).has_value());
}

}  // namespace
}  // namespace rfidray::localization
