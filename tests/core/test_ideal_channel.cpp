// The ideal (free-space line-of-sight) channel: h = √(G_R G_T)·λ/(4πD)·e^{−jkD}.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "core/channel.h"
#include "core/error.h"
#include "core/units.h"

namespace rfidray {
namespace {

Endpoint endpoint(const Vec3& p, const AntennaPattern& pattern = isotropic_pattern(0.0),
                  const Quat& q = Quat::Identity()) {
  Endpoint e;
  e.pose.position = p;
  e.pose.orientation = q;
  e.pattern = pattern;
  return e;
}

std::complex<double> h_of(const Endpoint& a, const Endpoint& t, double f) {
  IdealChannel ch;
  const std::vector<Endpoint> tags{t};
  std::complex<double> h;
  ch.one_way(a, tags, f, std::span<std::complex<double>>(&h, 1));
  return h;
}

// D = 2 m, 865.7 MHz, isotropic: |h| = λ/(4πD) = 0.34630063301/25.13274123 = 0.0137788644;
// arg h = −kD = −2π·2/0.34630063301 = −36.28746071 rad ≡ −36.28746071 + 6·2π = 1.41165113 rad.
TEST(IdealChannel, FriisMagnitudeAndPhase) {
  const Endpoint a = endpoint(Vec3(1.0, 2.0, 1.5));
  const Endpoint t = endpoint(Vec3(1.0, 2.0, 1.5) + Vec3(1.2, -1.6, 0.0));  // D = 2
  const std::complex<double> h = h_of(a, t, 865.7e6);
  EXPECT_NEAR(std::abs(h), 0.0137788644, 1e-10);
  EXPECT_NEAR(wrap_to_pi(std::arg(h) - 1.41165113), 0.0, 1e-8);
  for (double d : {0.05, 0.7, 3.3, 12.0})
    for (double f : {865.7e6, 915e6}) {
      const std::complex<double> hd = h_of(a, endpoint(a.pose.position + d * Vec3(0, 0.6, 0.8)), f);
      const double lambda = wavelength_m(f);
      EXPECT_NEAR(std::abs(hd) / (lambda / (4 * kPi * d)), 1.0, 1e-12);
      EXPECT_NEAR(wrap_to_pi(std::arg(hd) + kTwoPi * d / lambda), 0.0, 1e-12);
    }
}

// Gains in the LoS direction: 6 dBi reader, dipole tag broadside (1.64) → |h| scales by √(3.981072·1.64).
TEST(IdealChannel, PatternGainsInLineOfSightDirection) {
  AntennaPattern dipole;
  dipole.kind = PatternKind::kDipole;
  const Endpoint a = endpoint(Vec3::Zero(), isotropic_pattern(6.0));
  const Endpoint t = endpoint(Vec3(3.0, 0.0, 0.0), dipole);  // wire along Z, link along X: broadside
  const double free = wavelength_m(865.7e6) / (4 * kPi * 3.0);
  EXPECT_NEAR(std::abs(h_of(a, t, 865.7e6)) / free, std::sqrt(std::pow(10.0, 0.6) * 1.64), 1e-12);
  // Tag wire pointing at the reader: no coupling.
  const Endpoint t_axis = endpoint(Vec3(0.0, 0.0, 3.0), dipole);
  EXPECT_NEAR(std::abs(h_of(a, t_axis, 865.7e6)), 0.0, 1e-15);
  // A patch reader facing away sees the tag at its front-to-back floor (−20 dB → amplitude × 0.1).
  AntennaPattern patch;
  patch.kind = PatternKind::kPatch;
  patch.peak_gain_dbi = 8.0;
  patch.beamwidth_deg = 60.0;
  const Endpoint facing = endpoint(Vec3::Zero(), patch);
  const Endpoint away = endpoint(Vec3::Zero(), patch, Quat(Eigen::AngleAxisd(kPi, Vec3::UnitZ())));
  const Endpoint iso_tag = endpoint(Vec3(3.0, 0.0, 0.0));
  EXPECT_NEAR(std::abs(h_of(away, iso_tag, 865.7e6)) / std::abs(h_of(facing, iso_tag, 865.7e6)), 0.1, 1e-12);
}

TEST(IdealChannel, PathsAgreeWithOneWay) {
  IdealChannel ch;
  EXPECT_EQ(ch.name(), "ideal");
  EXPECT_TRUE(ch.cacheable());
  const Endpoint a = endpoint(Vec3(0, 0, 1), isotropic_pattern(3.0));
  const Endpoint t = endpoint(Vec3(2, 1, 2), isotropic_pattern(2.0));
  const auto paths = ch.paths(a, t, 866.9e6);
  ASSERT_EQ(paths.size(), 1u);
  EXPECT_EQ(paths[0].kind, PathKind::kLineOfSight);
  EXPECT_NEAR(paths[0].length_m, std::sqrt(6.0), 1e-15);
  EXPECT_NEAR(paths[0].coefficient.real(), std::sqrt(std::pow(10.0, 0.3) * std::pow(10.0, 0.2)), 1e-12);
  EXPECT_EQ(paths[0].coefficient.imag(), 0.0);
  EXPECT_EQ(sum_paths(paths), h_of(a, t, 866.9e6));
  // Batch of several tags.
  const std::vector<Endpoint> tags{endpoint(Vec3(1, 0, 1)), endpoint(Vec3(0, 3, 1)), endpoint(Vec3(0, 0, 6))};
  std::vector<std::complex<double>> h(3);
  ch.one_way(a, tags, 866.9e6, h);
  for (size_t i = 0; i < 3; ++i) EXPECT_EQ(h[i], sum_paths(ch.paths(a, tags[i], 866.9e6)));
}

TEST(IdealChannel, CoincidentOrNonFiniteEndpointsThrow) {
  IdealChannel ch;
  const Endpoint a = endpoint(Vec3(1, 1, 1));
  EXPECT_THROW(ch.paths(a, endpoint(Vec3(1, 1, 1)), 865.7e6), InputError);
  EXPECT_THROW(h_of(a, endpoint(Vec3(1, 1, 1)), 865.7e6), InputError);
  EXPECT_THROW(h_of(a, endpoint(Vec3(NAN, 1, 1)), 865.7e6), InputError);
  EXPECT_THROW(h_of(a, endpoint(Vec3(INFINITY, 1, 1)), 865.7e6), InputError);
  EXPECT_THROW(h_of(a, endpoint(Vec3(2, 1, 1)), 0.0), InputError);
  EXPECT_THROW(h_of(a, endpoint(Vec3(2, 1, 1)), -865.7e6), InputError);
  EXPECT_THROW(ch.paths(a, endpoint(Vec3(2, 1, 1)), NAN), InputError);
}

}  // namespace
}  // namespace rfidray
