// ITU-R P.2040 Table 3 radio materials: ε' = a·f^b, σ = c·f^d (f in GHz), η = ε' − jσ/(ωε0).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/material.h"

namespace rfidray {
namespace {

// ω ε0 at 1 GHz = 2π·1e9 · 8.8541878128e-12 = 0.0556325028 S/m.
constexpr double kOmegaEps0At1GHz = 0.0556325028;

struct Expected {
  const char* name;
  double eps_r;
  double sigma_1ghz;      // = c
  double sigma_865;       // c·0.8657^d
  double im_eta_865;      // −σ/(ω ε0) at 865.7 MHz
  bool extrapolated_865;  // 865.7 MHz below the Table 3 range
};

// Hand arithmetic at 865.7 MHz (f = 0.8657 GHz, ln f = −0.1442168):
//  concrete     0.8657^0.7822 = e^{−0.1128064} = 0.8933236 → σ = 0.0462·0.8933236 = 0.04127155;
//               −Im η = 0.04127155 / (0.0556325028·0.8657) = 0.8569486
//  brick        0.8657^0.16   = e^{−0.0230747} = 0.9771895 → σ = 0.02325711, −Im η = 0.4829028
//  plasterboard 0.8657^0.9395 = e^{−0.1354917} = 0.8732864 → σ = 0.007422934, −Im η = 0.1541273
//  wood         0.8657^1.0718 = e^{−0.1545716} = 0.8567821 → σ = 0.004026876, −Im η = 0.08361270
//  glass        0.8657^1.3394 = e^{−0.1931640} = 0.8243467 → σ = 0.002967648, −Im η = 0.06161925
const Expected kTable[] = {
    {"concrete", 5.24, 0.0462, 0.04127155, -0.8569486, true},
    {"brick", 3.91, 0.0238, 0.02325711, -0.4829028, true},
    {"plasterboard", 2.73, 0.0085, 0.007422934, -0.1541273, true},
    {"wood", 1.99, 0.0047, 0.004026876, -0.08361270, false},   // Table 3: 0.001–100 GHz
    {"glass", 6.31, 0.0036, 0.002967648, -0.06161925, false},  // Table 3: 0.1–100 GHz
};

TEST(Material, ValuesAt1GHz) {
  for (const Expected& e : kTable) {
    const auto m = builtin_material(e.name);
    ASSERT_TRUE(m) << e.name;
    EXPECT_DOUBLE_EQ(m->relative_permittivity(1e9), e.eps_r) << e.name;  // b = 0
    EXPECT_DOUBLE_EQ(m->conductivity_s_m(1e9), e.sigma_1ghz) << e.name;  // f^d = 1
    const auto eta = m->complex_permittivity(1e9);
    EXPECT_DOUBLE_EQ(eta.real(), e.eps_r);
    EXPECT_NEAR(eta.imag(), -e.sigma_1ghz / kOmegaEps0At1GHz, 1e-8) << e.name;
    EXPECT_FALSE(m->extrapolated(1e9)) << e.name;
    EXPECT_FALSE(m->perfect_conductor);
  }
  // concrete: −0.0462 / 0.0556325028 = −0.8304498
  EXPECT_NEAR(builtin_material("concrete")->complex_permittivity(1e9).imag(), -0.8304498, 1e-7);
}

TEST(Material, ValuesAt865MHz) {
  for (const Expected& e : kTable) {
    const auto m = builtin_material(e.name);
    ASSERT_TRUE(m) << e.name;
    EXPECT_DOUBLE_EQ(m->relative_permittivity(865.7e6), e.eps_r) << e.name;
    EXPECT_NEAR(m->conductivity_s_m(865.7e6), e.sigma_865, 1e-6 * e.sigma_865) << e.name;
    EXPECT_NEAR(m->complex_permittivity(865.7e6).imag(), e.im_eta_865, 1e-6 * std::abs(e.im_eta_865)) << e.name;
    EXPECT_EQ(m->extrapolated(865.7e6), e.extrapolated_865) << e.name;
  }
}

TEST(Material, FrequencyRanges) {
  EXPECT_TRUE(builtin_material("brick")->extrapolated(41e9));  // brick fit: 1–40 GHz
  EXPECT_FALSE(builtin_material("brick")->extrapolated(40e9));
  EXPECT_TRUE(builtin_material("concrete")->extrapolated(999e6));
  EXPECT_TRUE(builtin_material("glass")->extrapolated(50e6));
  EXPECT_FALSE(builtin_material("wood")->extrapolated(50e6));
}

TEST(Material, MetalIsPerfectConductor) {
  const auto m = builtin_material("metal");
  ASSERT_TRUE(m);
  EXPECT_TRUE(m->perfect_conductor);
  EXPECT_FALSE(m->extrapolated(865.7e6));  // the PEC model does not use the fit
  EXPECT_DOUBLE_EQ(m->conductivity_s_m(865.7e6), 1e7);
  // σ/(ωε0) = 1e7 / (0.0556325028·0.8657) ≈ 2.08e8 ≫ ε' = 1
  EXPECT_LT(m->complex_permittivity(865.7e6).imag(), -1e8);
}

TEST(Material, NamesAndUnknown) {
  const auto names = builtin_material_names();
  for (const char* n : {"concrete", "brick", "plasterboard", "wood", "glass", "metal", "water"})
    EXPECT_NE(std::find(names.begin(), names.end(), n), names.end()) << n;
  EXPECT_EQ(names.size(), 7u);
  EXPECT_FALSE(builtin_material("unobtainium"));
  EXPECT_FALSE(builtin_material("Concrete"));
}

// Water's power law against the Debye relaxation it stands for (Kaatze 1989, 25 °C), computed here.
TEST(Material, WaterFollowsItsDebyeRelaxation) {
  const auto m = builtin_material("water");
  ASSERT_TRUE(m);
  for (double f : {0.1e9, 0.866e9, 2e9, 3e9}) {
    const double omega = 2.0 * 3.14159265358979 * f, tau = 8.27e-12, es = 78.36, einf = 5.2;
    const std::complex<double> debye = einf + (es - einf) / std::complex<double>(1.0, omega * tau);
    const double sigma = -debye.imag() * omega * 8.8541878128e-12;
    EXPECT_NEAR(m->relative_permittivity(f), debye.real(), 0.03 * debye.real()) << f;
    EXPECT_NEAR(m->conductivity_s_m(f), sigma, 0.03 * sigma) << f;
    EXPECT_FALSE(m->extrapolated(f));
  }
  EXPECT_TRUE(m->extrapolated(5e9));
}

TEST(Material, UserMaterial) {
  const RadioMaterial m = user_material("cardboard", 2.0, 0.01, 0.005);
  EXPECT_EQ(m.name, "cardboard");
  EXPECT_DOUBLE_EQ(m.relative_permittivity(865.7e6), 2.0);
  EXPECT_DOUBLE_EQ(m.relative_permittivity(5e9), 2.0);
  EXPECT_DOUBLE_EQ(m.conductivity_s_m(865.7e6), 0.01);
  EXPECT_DOUBLE_EQ(m.thickness_m, 0.005);
  EXPECT_FALSE(m.extrapolated(865.7e6));
  // −0.01 / (0.0556325028·0.8657) = −0.01 / 0.04816106 = −0.2076366
  EXPECT_NEAR(m.complex_permittivity(865.7e6).imag(), -0.2076366, 1e-6);
  EXPECT_THROW(user_material("x", 0.5, 0.0, 0.0), InputError);
  EXPECT_THROW(user_material("x", NAN, 0.0, 0.0), InputError);
  EXPECT_THROW(user_material("x", 2.0, -1.0, 0.0), InputError);
  EXPECT_THROW(user_material("x", 2.0, 0.0, -0.1), InputError);
  EXPECT_THROW(user_material("x", 2.0, 0.0, INFINITY), InputError);
  try {
    user_material("drywall", 2.0, -1.0, 0.0);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("materials.drywall.sigma"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rfidray
