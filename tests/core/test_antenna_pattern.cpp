// Antenna gain patterns: isotropic, half-wave dipole, cos^n patch, azimuth × elevation table.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/antenna_pattern.h"
#include "core/error.h"
#include "core/units.h"

namespace rfidray {
namespace {

Vec3 spherical(double theta_from_z, double phi) {
  return Vec3(std::sin(theta_from_z) * std::cos(phi), std::sin(theta_from_z) * std::sin(phi), std::cos(theta_from_z));
}

// ∫ G dΩ over the sphere (midpoint rule in θ, φ); 4π for any lossless pattern normalised to its directivity.
double integrate_gain(const AntennaPattern& p) {
  const int nt = 720, np = 360;
  double sum = 0.0;
  for (int i = 0; i < nt; ++i) {
    const double th = (i + 0.5) * kPi / nt;
    for (int j = 0; j < np; ++j) sum += p.gain_linear(spherical(th, (j + 0.5) * kTwoPi / np)) * std::sin(th);
  }
  return sum * (kPi / nt) * (kTwoPi / np);
}

TEST(AntennaPattern, Isotropic) {
  const AntennaPattern p = isotropic_pattern(3.0);
  for (const Vec3& d : {Vec3(1, 0, 0), Vec3(0, -1, 0), Vec3(0.3, 0.2, -0.9)})
    EXPECT_NEAR(p.gain_linear(d), std::pow(10.0, 0.3), 1e-12);
  EXPECT_NO_THROW(p.validate("a"));
}

// Half-wave dipole along local Z: G(θ) = 1.64·[cos(π/2·cosθ)/sinθ]². Broadside 1.64, axis 0;
// θ = 60°: 1.64·cos²(π/4)/sin²60° = 1.64·0.5/0.75 = 1.093333.
TEST(AntennaPattern, Dipole) {
  AntennaPattern p;
  p.kind = PatternKind::kDipole;
  EXPECT_DOUBLE_EQ(p.gain_linear(Vec3::UnitX()), 1.64);
  EXPECT_DOUBLE_EQ(p.gain_linear(Vec3(0.0, -2.0, 0.0)), 1.64);  // unnormalised direction
  EXPECT_EQ(p.gain_linear(Vec3::UnitZ()), 0.0);
  EXPECT_EQ(p.gain_linear(-Vec3::UnitZ()), 0.0);
  EXPECT_NEAR(p.gain_linear(spherical(kPi / 3.0, 0.7)), 1.093333333, 1e-9);
  for (double th = 0.05; th < kPi; th += 0.1) EXPECT_LE(p.gain_linear(spherical(th, 1.0)), 1.64 + 1e-12);
  // Directivity 1.64 means ∫G dΩ ≈ 4π (1.64 is the rounded 1.6409).
  EXPECT_NEAR(integrate_gain(p) / (4.0 * kPi), 1.0, 2e-3);
}

// Patch with a 60° half-power beamwidth: G(30°) = peak/2.
TEST(AntennaPattern, PatchBeamwidth) {
  AntennaPattern p;
  p.kind = PatternKind::kPatch;
  p.peak_gain_dbi = 8.0;
  p.beamwidth_deg = 60.0;
  const double peak = std::pow(10.0, 0.8);
  EXPECT_NEAR(p.gain_linear(Vec3::UnitX()), peak, 1e-12);
  for (double phi : {0.0, 1.0, 2.0})
    EXPECT_NEAR(p.gain_linear(Vec3(std::cos(kPi / 6), std::sin(kPi / 6) * std::cos(phi), std::sin(kPi / 6) * std::sin(phi))),
                peak / 2.0, 1e-12);
  // n = ln 0.5 / ln cos 30° = −0.693147 / −0.143841 = 4.818842
  EXPECT_NEAR(p.patch_exponent(), 4.818842, 1e-6);
  EXPECT_NO_THROW(p.validate("a"));
}

// Front-to-back: behind the ground plane (and at 90°) the gain is the floor peak·10^(−FB/10).
TEST(AntennaPattern, PatchFrontToBackFloor) {
  AntennaPattern p;
  p.kind = PatternKind::kPatch;
  p.peak_gain_dbi = 8.0;
  p.beamwidth_deg = 60.0;
  p.front_to_back_db = 20.0;
  const double floor = std::pow(10.0, 0.8) * 0.01;
  EXPECT_NEAR(p.gain_linear(-Vec3::UnitX()), floor, 1e-15);
  EXPECT_NEAR(p.gain_linear(Vec3::UnitY()), floor, 1e-15);
  EXPECT_NEAR(p.gain_linear(Vec3(-1, 1, 1)), floor, 1e-15);
  EXPECT_NEAR(p.gain_linear(Vec3(0.01, 1, 0)), floor, 1e-15);  // cos^n below the floor near 90°
  p.front_to_back_db = 30.0;
  EXPECT_NEAR(p.gain_linear(-Vec3::UnitX()), floor * 0.1, 1e-15);
}

// Without a beamwidth the exponent comes from the gain: directivity of cos^n over a hemisphere is 2(n+1).
// 9 dBi = 7.943282 → n = 7.943282/2 − 1 = 2.971641; ∫G dΩ = 4π plus the floor's share.
TEST(AntennaPattern, PatchFromGainConservesPower) {
  AntennaPattern p;
  p.kind = PatternKind::kPatch;
  p.peak_gain_dbi = 9.0;
  p.front_to_back_db = 60.0;  // floor 1e-6 of the peak: negligible
  EXPECT_NEAR(p.patch_exponent(), 2.971641, 1e-6);
  EXPECT_NEAR(integrate_gain(p) / (4.0 * kPi), 1.0, 2e-3);
}

TEST(AntennaPattern, WorldOrientation) {
  AntennaPattern p;
  p.kind = PatternKind::kPatch;
  p.peak_gain_dbi = 8.0;
  p.beamwidth_deg = 60.0;
  const Quat yaw90(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ()));  // boresight now +Y
  EXPECT_NEAR(p.gain_linear_world(yaw90, Vec3::UnitY()), std::pow(10.0, 0.8), 1e-12);
  EXPECT_NEAR(p.gain_linear_world(yaw90, Vec3::UnitX()), std::pow(10.0, 0.8) * 0.01, 1e-12);
  AntennaPattern dip;
  dip.kind = PatternKind::kDipole;
  const Quat roll90(Eigen::AngleAxisd(kPi / 2, Vec3::UnitX()));  // wire now along −Y
  EXPECT_NEAR(dip.gain_linear_world(roll90, Vec3::UnitY()), 0.0, 1e-12);
  EXPECT_NEAR(dip.gain_linear_world(roll90, Vec3::UnitZ()), 1.64, 1e-12);
}

std::shared_ptr<PatternTable> small_table() {
  auto t = std::make_shared<PatternTable>();
  t->azimuth_deg = {-90.0, 0.0, 90.0};
  t->elevation_deg = {-30.0, 0.0, 30.0};
  // rows: elevation −30, 0, 30; columns: azimuth −90, 0, 90
  t->gain_dbi = {-10.0, 0.0, -6.0,  //
                 -4.0, 6.0, 2.0,    //
                 -8.0, 1.0, -2.0};
  return t;
}

Vec3 azel(double az_deg, double el_deg) {
  const double az = az_deg * kPi / 180.0, el = el_deg * kPi / 180.0;
  return Vec3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
}

TEST(AntennaPattern, TableGridPointsAndBilinear) {
  AntennaPattern p;
  p.kind = PatternKind::kTable;
  p.table = small_table();
  ASSERT_NO_THROW(p.validate("a"));
  auto dbi = [&](double az, double el) { return linear_to_db(p.gain_linear(azel(az, el))); };
  EXPECT_NEAR(dbi(0, 0), 6.0, 1e-9);
  EXPECT_NEAR(dbi(-90, -30), -10.0, 1e-9);
  EXPECT_NEAR(dbi(90, 30), -2.0, 1e-9);
  EXPECT_NEAR(dbi(90, 0), 2.0, 1e-9);
  // Along azimuth at el 0: halfway between 6 and 2 → 4.
  EXPECT_NEAR(dbi(45, 0), 4.0, 1e-9);
  // Along elevation at az 0: a third of the way from 6 to 1 → 6 − 5/3 = 4.333333.
  EXPECT_NEAR(dbi(0, 10), 6.0 - 5.0 / 3.0, 1e-9);
  // Bilinear in the cell az [0, 90], el [0, 30] at (45, 15): mean of 6, 2, 1, −2 = 1.75.
  EXPECT_NEAR(dbi(45, 15), 1.75, 1e-9);
  // (22.5, 7.5): weights (0.25, 0.25): 0.75·(0.75·6 + 0.25·2) + 0.25·(0.75·1 + 0.25·(−2)) = 3.75 + 0.0625 = 3.8125.
  EXPECT_NEAR(dbi(22.5, 7.5), 3.8125, 1e-9);
  // Elevation clamps beyond the table.
  EXPECT_NEAR(dbi(0, 60), 1.0, 1e-9);
}

// Azimuth wraps: the grid covers [−90, 90]; 180° lies halfway across the 180° gap from +90 (2 dBi) to
// −90 (−4 dBi) at el 0 → −1 dBi; 135° is a quarter of the way → 2 − 1.5 = 0.5.
TEST(AntennaPattern, TableAzimuthWraps) {
  AntennaPattern p;
  p.kind = PatternKind::kTable;
  p.table = small_table();
  auto dbi = [&](double az, double el) { return linear_to_db(p.gain_linear(azel(az, el))); };
  EXPECT_NEAR(dbi(180, 0), -1.0, 1e-9);
  EXPECT_NEAR(dbi(-180, 0), -1.0, 1e-9);
  EXPECT_NEAR(dbi(135, 0), 0.5, 1e-9);
  EXPECT_NEAR(dbi(-135, 0), -2.5, 1e-9);
  // A full −180..180 grid interpolates normally and agrees at the seam.
  auto t = std::make_shared<PatternTable>();
  t->azimuth_deg = {-180.0, 0.0, 180.0};
  t->elevation_deg = {0.0};
  t->gain_dbi = {3.0, 5.0, 3.0};
  p.table = t;
  ASSERT_NO_THROW(p.validate("a"));
  EXPECT_NEAR(dbi(90, 0), 4.0, 1e-9);
  EXPECT_NEAR(dbi(-179.999, 0), 3.0, 1e-4);
  EXPECT_NEAR(dbi(179.999, 0), 3.0, 1e-4);
}

std::string validate_error(const AntennaPattern& p) {
  try {
    p.validate("antennas[0].pattern");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// max_gain_linear bounds every direction and is reached (the edge-end check prunes edges with it).
TEST(AntennaPattern, MaxGainBoundsEveryDirectionAndIsReached) {
  AntennaPattern dipole;
  dipole.kind = PatternKind::kDipole;
  AntennaPattern patch;
  patch.kind = PatternKind::kPatch;
  patch.peak_gain_dbi = 6.0;
  patch.beamwidth_deg = 70.0;
  AntennaPattern table;
  table.kind = PatternKind::kTable;
  table.table = small_table();
  for (const AntennaPattern& p : {isotropic_pattern(3.0), dipole, patch, table}) {
    double largest = 0.0;
    for (int i = 0; i <= 180; ++i)
      for (int j = 0; j < 360; ++j) {
        const double g = p.gain_linear(spherical(i * kPi / 180.0, j * kTwoPi / 360.0));
        EXPECT_LE(g, p.max_gain_linear() * (1 + 1e-12)) << to_string(p.kind);
        largest = std::max(largest, g);
      }
    // The 1° grid holds each pattern's maximum (broadside, boresight, the table's 6 dBi at az 0, el 0).
    EXPECT_NEAR(largest, p.max_gain_linear(), 1e-12 * largest) << to_string(p.kind);
  }
}

TEST(AntennaPattern, ValidateErrors) {
  AntennaPattern p;
  p.peak_gain_dbi = NAN;
  EXPECT_NE(validate_error(p).find("antennas[0].pattern.gain_dbi"), std::string::npos);
  AntennaPattern patch;
  patch.kind = PatternKind::kPatch;
  patch.peak_gain_dbi = 8.0;
  patch.beamwidth_deg = 180.0;
  EXPECT_NE(validate_error(patch).find("beamwidth_deg"), std::string::npos);
  patch.beamwidth_deg = -1.0;
  EXPECT_NE(validate_error(patch).find("beamwidth_deg"), std::string::npos);
  patch.beamwidth_deg = 0.0;
  patch.peak_gain_dbi = 2.0;  // no beamwidth and gain ≤ 3 dBi: n would be ≤ 0
  EXPECT_NE(validate_error(patch).find("gain_dbi"), std::string::npos);
  patch.peak_gain_dbi = 8.0;
  patch.front_to_back_db = -3.0;
  EXPECT_NE(validate_error(patch).find("front_to_back_db"), std::string::npos);

  AntennaPattern table;
  table.kind = PatternKind::kTable;
  EXPECT_NE(validate_error(table).find("table"), std::string::npos);  // missing
  auto t = small_table();
  t->gain_dbi.pop_back();
  table.table = t;
  EXPECT_NE(validate_error(table).find("table"), std::string::npos);  // size mismatch
  t = small_table();
  t->azimuth_deg = {0.0, -90.0, 90.0};
  table.table = t;
  EXPECT_NE(validate_error(table).find("increasing"), std::string::npos);
  t = small_table();
  t->elevation_deg = {-30.0, 0.0, 0.0};
  table.table = t;
  EXPECT_NE(validate_error(table).find("increasing"), std::string::npos);
  t = small_table();
  t->gain_dbi[4] = INFINITY;
  table.table = t;
  EXPECT_NE(validate_error(table).find("finite"), std::string::npos);
  t = small_table();
  t->azimuth_deg = {-90.0, 0.0, 200.0};
  table.table = t;
  EXPECT_NE(validate_error(table).find("[-180, 180]"), std::string::npos);
  table.table = small_table();
  EXPECT_EQ(validate_error(table), "");
}

TEST(AntennaPattern, ParseKind) {
  EXPECT_EQ(parse_pattern_kind("patch", "f"), PatternKind::kPatch);
  for (PatternKind k : {PatternKind::kIsotropic, PatternKind::kDipole, PatternKind::kPatch, PatternKind::kTable})
    EXPECT_EQ(parse_pattern_kind(to_string(k), "f"), k);
  try {
    parse_pattern_kind("yagi", "antennas[2].pattern");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("antennas[2].pattern"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("yagi"), std::string::npos);
  }
}

}  // namespace
}  // namespace rfidray
