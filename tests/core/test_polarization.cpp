// Polarization field vectors and the reciprocity match e_rx · e_in.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "core/error.h"
#include "core/polarization.h"
#include "core/units.h"

namespace rfidray {
namespace {

using C = std::complex<double>;

const Polarization kRhcp{PolarizationKind::kCircularRight, Vec3::UnitZ()};
const Polarization kLhcp{PolarizationKind::kCircularLeft, Vec3::UnitZ()};
Polarization linear(const Vec3& axis) { return Polarization{PolarizationKind::kLinear, axis}; }

// Antenna A at the origin radiates along +X; B sits on +X facing back (yaw 180°). Returns the match at B.
C facing_match(const Polarization& a, const Polarization& b, const Quat& qa = Quat::Identity()) {
  const Quat qb(Eigen::AngleAxisd(kPi, Vec3::UnitZ()));
  const Vec3 dir = Vec3::UnitX();
  return polarization_match(a.field(qa, dir), b, qb, dir);
}

TEST(Polarization, FieldsAreUnitAndTransverse) {
  const Quat q(Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()));
  for (const Polarization& p : {kRhcp, kLhcp, linear(Vec3::UnitZ()), linear(Vec3(1, 1, 0))})
    for (const Vec3& d : std::vector<Vec3>{Vec3::UnitX(), Vec3(0.3, -0.5, 0.8).normalized(), Vec3::UnitZ()}) {
      const CVec3 e = p.field(q, d);
      EXPECT_NEAR(e.norm(), 1.0, 1e-12);
      EXPECT_NEAR(std::abs(d.cast<C>().dot(e)), 0.0, 1e-12);
    }
}

TEST(Polarization, CircularPairs) {
  EXPECT_NEAR(std::abs(facing_match(kRhcp, kRhcp)), 1.0, 1e-12);  // same hand facing each other: matched
  EXPECT_NEAR(std::abs(facing_match(kLhcp, kLhcp)), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(facing_match(kRhcp, kLhcp)), 0.0, 1e-12);  // opposite hands: rejected
  EXPECT_NEAR(std::abs(facing_match(kLhcp, kRhcp)), 0.0, 1e-12);
  // Rolling the transmitter about the link axis only changes the phase.
  const Quat roll(Eigen::AngleAxisd(0.7, Vec3::UnitX()));
  EXPECT_NEAR(std::abs(facing_match(kRhcp, kRhcp, roll)), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(facing_match(kRhcp, kLhcp, roll)), 0.0, 1e-12);
}

TEST(Polarization, LinearVersusCircular) {
  for (const Vec3& axis : std::vector<Vec3>{Vec3::UnitZ(), Vec3::UnitY(), Vec3(0, 1, 1)}) {
    EXPECT_NEAR(std::abs(facing_match(linear(axis), kRhcp)), 1.0 / std::sqrt(2.0), 1e-12);
    EXPECT_NEAR(std::abs(facing_match(kLhcp, linear(axis))), 1.0 / std::sqrt(2.0), 1e-12);
  }
}

TEST(Polarization, LinearPairs) {
  EXPECT_NEAR(std::abs(facing_match(linear(Vec3::UnitZ()), linear(Vec3::UnitZ()))), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(facing_match(linear(Vec3::UnitZ()), linear(Vec3::UnitY()))), 0.0, 1e-12);  // crossed
  // Tilted by 60° about the link: |cos 60°| = 0.5 amplitude.
  EXPECT_NEAR(std::abs(facing_match(linear(Vec3::UnitZ()), linear(Vec3(0, std::sin(kPi / 3), std::cos(kPi / 3))))),
              0.5, 1e-12);
  // A linear axis along the propagation direction radiates nothing that way.
  EXPECT_EQ(linear(Vec3::UnitX()).field(Quat::Identity(), Vec3::UnitX()).norm(), 0.0);
  EXPECT_EQ(std::abs(facing_match(linear(Vec3::UnitX()), linear(Vec3::UnitZ()))), 0.0);
  EXPECT_EQ(std::abs(facing_match(linear(Vec3::UnitZ()), linear(Vec3::UnitX()))), 0.0);
  // An axis partly along the link is projected: 45° tilt towards the link → unit field along Z anyway.
  const CVec3 e = linear(Vec3(1, 0, 1)).field(Quat::Identity(), Vec3::UnitX());
  EXPECT_NEAR(std::abs(e(2)), 1.0, 1e-12);
}

// IEEE RHCP: E turns right-handed about k̂ (clockwise seen looking along k̂). With e^{jωt}, Re{e·e^{jωt}}
// at ωt = 0 is u and a quarter period later v = k̂ × u, so (E(0) × E(T/4))·k̂ > 0.
TEST(Polarization, RhcpRotatesRightHandedAboutPropagation) {
  const Vec3 k = Vec3::UnitX();
  const CVec3 e = kRhcp.field(Quat::Identity(), k);
  const Vec3 at0 = e.real();
  const Vec3 at90 = (e * C(0, 1)).real();  // e^{jπ/2}
  EXPECT_NEAR(at0.cross(at90).normalized().dot(k), 1.0, 1e-12);
  const CVec3 l = kLhcp.field(Quat::Identity(), k);
  EXPECT_NEAR(Vec3(l.real()).cross(Vec3((l * C(0, 1)).real())).normalized().dot(k), -1.0, 1e-12);
}

TEST(Polarization, CircularWithAxisAlongPropagationStillDefined) {
  const CVec3 e = kRhcp.field(Quat::Identity(), Vec3::UnitZ());  // reference axis Z parallel to k
  EXPECT_NEAR(e.norm(), 1.0, 1e-12);
  EXPECT_NEAR(std::abs(e(2)), 0.0, 1e-12);
}

TEST(Polarization, ParseKind) {
  EXPECT_EQ(parse_polarization_kind("linear", "f"), PolarizationKind::kLinear);
  EXPECT_EQ(parse_polarization_kind("rhcp", "f"), PolarizationKind::kCircularRight);
  EXPECT_EQ(parse_polarization_kind("circular", "f"), PolarizationKind::kCircularRight);
  EXPECT_EQ(parse_polarization_kind("lhcp", "f"), PolarizationKind::kCircularLeft);
  for (PolarizationKind k : {PolarizationKind::kLinear, PolarizationKind::kCircularRight, PolarizationKind::kCircularLeft})
    EXPECT_EQ(parse_polarization_kind(to_string(k), "f"), k);
  try {
    parse_polarization_kind("elliptical", "tags[3].polarization");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tags[3].polarization"), std::string::npos);
  }
}

}  // namespace
}  // namespace rfidray
