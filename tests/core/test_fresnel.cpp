// Fresnel reflection/transmission (half-space and P.2040 slab) and the polarized-field mapping.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <vector>

#include "core/error.h"
#include "core/fresnel.h"
#include "core/units.h"

namespace rfidray {
namespace {

using C = std::complex<double>;
constexpr double kF = 865.7e6;

std::vector<C> test_etas() {
  std::vector<C> etas = {C(1.99, 0), C(2.73, 0), C(5.24, 0), C(6.31, 0), C(30.0, 0)};
  for (const char* n : {"concrete", "brick", "plasterboard", "wood", "glass"})
    etas.push_back(builtin_material(n)->complex_permittivity(kF));
  etas.push_back(C(15.0, -40.0));  // very lossy (wet ground-like)
  return etas;
}

TEST(Fresnel, GrazingIncidenceGivesMinusOne) {
  for (C eta : test_etas()) {
    const FresnelCoefficients g = fresnel_reflection(eta, 0.0);
    EXPECT_NEAR(std::abs(g.te - C(-1.0, 0.0)), 0.0, 1e-15) << eta;
    EXPECT_NEAR(std::abs(g.tm - C(-1.0, 0.0)), 0.0, 1e-15) << eta;
    // Approaching grazing: |Γ + 1| shrinks ∝ cos θ (Γ_TE ≈ −1 + 2cosθ/√(η−1)).
    double prev_te = 2.0, prev_tm = 2.0;
    for (double c : {1e-1, 1e-2, 1e-3, 1e-4}) {
      const FresnelCoefficients h = fresnel_reflection(eta, c);
      EXPECT_LT(std::abs(h.te + 1.0), prev_te);
      EXPECT_LT(std::abs(h.tm + 1.0), prev_tm);
      prev_te = std::abs(h.te + 1.0);
      prev_tm = std::abs(h.tm + 1.0);
    }
    EXPECT_LT(prev_te, 1e-3);
    EXPECT_LT(prev_tm, 1e-2);
  }
}

// Lossless dielectric: tan θ_B = √ε' gives Γ_TM = 0 (and Γ_TE ≠ 0).
TEST(Fresnel, BrewsterAngleZeroesTm) {
  for (double eps : {1.99, 2.73, 3.91, 5.24, 6.31, 30.0}) {
    const double th = brewster_angle_rad(eps);
    EXPECT_NEAR(std::tan(th), std::sqrt(eps), 1e-12);
    const FresnelCoefficients g = fresnel_reflection(C(eps, 0.0), std::cos(th));
    EXPECT_LT(std::abs(g.tm), 1e-12) << eps;
    EXPECT_GT(std::abs(g.te), 0.1) << eps;
    // Just off Brewster, TM changes sign (real for lossless): minimum of |Γ_TM| is there.
    const double below = fresnel_reflection(C(eps, 0.0), std::cos(th - 0.05)).tm.real();
    const double above = fresnel_reflection(C(eps, 0.0), std::cos(th + 0.05)).tm.real();
    EXPECT_GT(below, 0.0);
    EXPECT_LT(above, 0.0);
  }
  EXPECT_THROW(brewster_angle_rad(0.0), InputError);
  EXPECT_THROW(brewster_angle_rad(NAN), InputError);
}

// Normal incidence: Γ_TE = (1 − √η)/(1 + √η); in our H-ratio TM convention Γ_TM = −Γ_TE (the reflected field
// vector is still Γ_TE·E_i, checked in ReflectField.NormalIncidenceScalesEveryPolarization).
// e.g. ε' = 4: Γ_TE = (1 − 2)/(1 + 2) = −1/3.
TEST(Fresnel, NormalIncidence) {
  EXPECT_NEAR(std::abs(fresnel_reflection(C(4.0, 0.0), 1.0).te - C(-1.0 / 3.0, 0.0)), 0.0, 1e-15);
  EXPECT_NEAR(std::abs(fresnel_reflection(C(4.0, 0.0), 1.0).tm - C(1.0 / 3.0, 0.0)), 0.0, 1e-15);
  for (C eta : test_etas()) {
    const C expected = (1.0 - std::sqrt(eta)) / (1.0 + std::sqrt(eta));
    const FresnelCoefficients g = fresnel_reflection(eta, 1.0);
    EXPECT_NEAR(std::abs(g.te - expected), 0.0, 1e-14) << eta;
    EXPECT_NEAR(std::abs(g.tm + expected), 0.0, 1e-14) << eta;
    const FresnelCoefficients t = fresnel_transmission(eta, 1.0);
    EXPECT_NEAR(std::abs(t.te - 2.0 / (1.0 + std::sqrt(eta))), 0.0, 1e-14);
    EXPECT_NEAR(std::abs(t.tm - t.te), 0.0, 1e-14);
  }
}

// Reflection coefficients of passive materials never exceed 1 in magnitude, at any angle, half-space or slab.
TEST(Fresnel, MagnitudeAtMostOne) {
  for (C eta : test_etas())
    for (int i = 0; i <= 90; ++i) {
      const double c = std::cos(i * kPi / 180.0);
      const FresnelCoefficients g = fresnel_reflection(eta, c);
      EXPECT_LE(std::abs(g.te), 1.0 + 1e-12) << eta << " " << i;
      EXPECT_LE(std::abs(g.tm), 1.0 + 1e-12) << eta << " " << i;
      for (double d : {0.01, 0.1, 0.3}) {
        const FresnelCoefficients r = slab_reflection(eta, c, d, kF);
        const FresnelCoefficients t = slab_transmission(eta, c, d, kF);
        // Power: |R|² + |T|² ≤ 1 (equality when lossless).
        EXPECT_LE(std::norm(r.te) + std::norm(t.te), 1.0 + 1e-12) << eta << " " << i << " " << d;
        EXPECT_LE(std::norm(r.tm) + std::norm(t.tm), 1.0 + 1e-12) << eta << " " << i << " " << d;
      }
    }
}

// Lossless half-space: |Γ|² + Re(√(η − sin²θ)/cos θ)·|T|² = 1 for both polarizations.
TEST(Fresnel, EnergyConservationLosslessHalfSpace) {
  for (double eps : {1.99, 3.91, 6.31, 30.0})
    for (int i = 0; i < 90; i += 5) {
      const double c = std::cos(i * kPi / 180.0);
      const C eta(eps, 0.0);
      const C root = std::sqrt(eta - (1.0 - c * c));
      const FresnelCoefficients g = fresnel_reflection(eta, c), t = fresnel_transmission(eta, c);
      const double w = (root / c).real();
      EXPECT_NEAR(std::norm(g.te) + w * std::norm(t.te), 1.0, 1e-12) << eps << " " << i;
      EXPECT_NEAR(std::norm(g.tm) + w * std::norm(t.tm), 1.0, 1e-12) << eps << " " << i;
    }
}

// Lossless slab in air: |R|² + |T|² = 1 exactly.
TEST(Fresnel, EnergyConservationLosslessSlab) {
  for (double eps : {2.73, 6.31})
    for (double d : {0.004, 0.05, 0.123})
      for (int i = 0; i < 90; i += 7) {
        const double c = std::cos(i * kPi / 180.0);
        const FresnelCoefficients r = slab_reflection(C(eps, 0.0), c, d, kF);
        const FresnelCoefficients t = slab_transmission(C(eps, 0.0), c, d, kF);
        EXPECT_NEAR(std::norm(r.te) + std::norm(t.te), 1.0, 1e-12);
        EXPECT_NEAR(std::norm(r.tm) + std::norm(t.tm), 1.0, 1e-12);
      }
}

// Half-wave slab at normal incidence: q = k0·d·√ε' = π → e^{−j2q} = 1 → R = 0 and |T| = 1.
// ε' = 4, f = 865.7 MHz: d = λ/(2·2) = 0.34630063301/4 = 0.0865752 m.
TEST(Fresnel, HalfWaveSlabIsTransparentAtNormalIncidence) {
  const double d = wavelength_m(kF) / 4.0;
  const FresnelCoefficients r = slab_reflection(C(4.0, 0.0), 1.0, d, kF);
  const FresnelCoefficients t = slab_transmission(C(4.0, 0.0), 1.0, d, kF);
  EXPECT_LT(std::abs(r.te), 1e-12);
  EXPECT_LT(std::abs(r.tm), 1e-12);
  EXPECT_NEAR(std::abs(t.te), 1.0, 1e-12);
  // Phase: T = e^{−j(q − q0)} = e^{−j(π − π/2)} = −j (q0 = k0 d = π/2).
  EXPECT_NEAR(std::abs(t.te - C(0.0, -1.0)), 0.0, 1e-12);
}

// A thick lossy slab hides its back face: R → half-space Γ and T → 0. Concrete at 865.7 MHz,
// √η ≈ 2.29 − 0.187j, so over 5 m the round trip decays as e^{−2·18.1·5·0.187} ≈ e^{−34}.
TEST(Fresnel, ThickLossySlabTendsToHalfSpace) {
  const C eta = builtin_material("concrete")->complex_permittivity(kF);
  for (int i = 0; i < 90; i += 10) {
    const double c = std::cos(i * kPi / 180.0);
    const FresnelCoefficients half = fresnel_reflection(eta, c);
    const FresnelCoefficients r = slab_reflection(eta, c, 5.0, kF);
    const FresnelCoefficients t = slab_transmission(eta, c, 5.0, kF);
    EXPECT_NEAR(std::abs(r.te - half.te), 0.0, 1e-12) << i;
    EXPECT_NEAR(std::abs(r.tm - half.tm), 0.0, 1e-12) << i;
    EXPECT_LT(std::abs(t.te), 1e-6);
    EXPECT_LT(std::abs(t.tm), 1e-6);
    // A thin slab differs clearly from the half-space.
    EXPECT_GT(std::abs(slab_reflection(eta, c, 0.02, kF).te - half.te), 1e-3) << i;
  }
}

TEST(Fresnel, VanishingSlabOrAirSlab) {
  for (C eta : test_etas())
    for (double c : {1.0, 0.7, 0.2}) {
      const FresnelCoefficients r = slab_reflection(eta, c, 0.0, kF);
      const FresnelCoefficients t = slab_transmission(eta, c, 0.0, kF);
      EXPECT_EQ(std::abs(r.te), 0.0);
      EXPECT_EQ(std::abs(r.tm), 0.0);
      EXPECT_NEAR(std::abs(t.te - 1.0), 0.0, 1e-15);
      EXPECT_NEAR(std::abs(t.tm - 1.0), 0.0, 1e-15);
    }
  // η = 1 (air) of any thickness: no reflection, T = 1 (the straight-line free-space phase is the caller's).
  const FresnelCoefficients t = slab_transmission(C(1.0, 0.0), 0.6, 0.37, kF);
  EXPECT_NEAR(std::abs(t.te - 1.0), 0.0, 1e-12);
  EXPECT_NEAR(std::abs(t.tm - 1.0), 0.0, 1e-12);
  EXPECT_NEAR(std::abs(slab_reflection(C(1.0, 0.0), 0.6, 0.37, kF).te), 0.0, 1e-15);
}

TEST(Fresnel, MaterialDispatch) {
  const RadioMaterial metal = *builtin_material("metal");
  for (double c : {1.0, 0.5, 0.01}) {
    const FresnelCoefficients g = material_reflection(metal, kF, c);
    EXPECT_EQ(g.te, C(-1.0, 0.0));
    EXPECT_EQ(g.tm, C(1.0, 0.0));
    const FresnelCoefficients t = material_transmission(metal, kF, c);
    EXPECT_EQ(t.te, C(0.0, 0.0));
    EXPECT_EQ(t.tm, C(0.0, 0.0));
  }
  RadioMaterial concrete = *builtin_material("concrete");
  const C eta = concrete.complex_permittivity(kF);
  EXPECT_EQ(material_reflection(concrete, kF, 0.6).te, fresnel_reflection(eta, 0.6).te);
  EXPECT_EQ(material_transmission(concrete, kF, 0.6).tm, fresnel_transmission(eta, 0.6).tm);
  concrete.thickness_m = 0.2;
  EXPECT_EQ(material_reflection(concrete, kF, 0.6).tm, slab_reflection(eta, 0.6, 0.2, kF).tm);
  EXPECT_EQ(material_transmission(concrete, kF, 0.6).te, slab_transmission(eta, 0.6, 0.2, kF).te);
  // cos θ from the back side is the same angle.
  EXPECT_EQ(material_reflection(concrete, kF, -0.6).te, material_reflection(concrete, kF, 0.6).te);
}

// ---- field mapping -------------------------------------------------------------------------------
CVec3 cvec(C x, C y, C z) { return CVec3(x, y, z); }

double cnorm(const CVec3& v) { return std::sqrt(v.squaredNorm()); }

// Directions hitting the z = 0 plane from above, with various azimuths.
std::vector<Vec3> incident_dirs() {
  std::vector<Vec3> v;
  for (double th : {0.0, 0.3, 0.8, 1.2, 1.55})
    for (double az : {0.0, 1.0, 2.5}) v.push_back(Vec3(std::sin(th) * std::cos(az), std::sin(th) * std::sin(az), -std::cos(th)));
  return v;
}

CVec3 transverse_field(const Vec3& k, C a, C b) {
  Vec3 u = k.cross(Vec3(0.3, 0.7, 0.2)).normalized();
  Vec3 v = k.cross(u);
  return a * u.cast<C>() + b * v.cast<C>();
}

// PEC: image theory — the reflected field is −E_tan + E_n: tangential E cancels at the surface.
// Norm is kept, and the reflected field is transverse to k̂_r.
TEST(ReflectField, PerfectConductorMirror) {
  const Vec3 n = Vec3::UnitZ();
  const FresnelCoefficients pec{C(-1, 0), C(1, 0)};
  for (const Vec3& k : incident_dirs())
    for (auto [a, b] : {std::pair<C, C>{1.0, 0.0}, {0.0, 1.0}, {0.6, C(0, 0.8)}, {C(0.3, 0.1), C(-0.2, 0.9)}}) {
      const CVec3 e = transverse_field(k, a, b);
      const CVec3 r = reflect_field(e, k, n, pec);
      const Vec3 kr = k - 2.0 * k.dot(n) * n;
      EXPECT_NEAR(cnorm(r), cnorm(e), 1e-12);
      EXPECT_NEAR(std::abs(kr.cast<C>().dot(r)), 0.0, 1e-12);
      const CVec3 image = -e + 2.0 * e(2) * n.cast<C>();
      EXPECT_NEAR(cnorm(r - image), 0.0, 1e-12) << k.transpose();
      // The normal may be given either way round.
      EXPECT_NEAR(cnorm(reflect_field(e, k, -n, pec) - r), 0.0, 1e-12);
    }
  // Normal incidence on a PEC mirror returns −E.
  const CVec3 e = cvec(0.6, C(0, 0.8), 0.0);
  EXPECT_NEAR(cnorm(reflect_field(e, -Vec3::UnitZ(), n, pec) + e), 0.0, 1e-15);
}

// At normal incidence the reflected field vector is (1 − √η)/(1 + √η)·E_i for every polarization.
TEST(ReflectField, NormalIncidenceScalesEveryPolarization) {
  const Vec3 n(0.0, 0.6, 0.8), k = -n;
  for (C eta : test_etas()) {
    const FresnelCoefficients g = fresnel_reflection(eta, 1.0);
    const C expected = (1.0 - std::sqrt(eta)) / (1.0 + std::sqrt(eta));
    for (auto [a, b] : {std::pair<C, C>{1.0, 0.0}, {0.0, 1.0}, {0.6, C(0, 0.8)}}) {
      const CVec3 e = transverse_field(k, a, b);
      EXPECT_NEAR(cnorm(reflect_field(e, k, n, g) - expected * e), 0.0, 1e-14) << eta;
    }
  }
}

// TE (along n × k̂) maps to Γ_TE times itself; TM stays in the plane of incidence, transverse to k̂_r,
// scaled by |Γ_TM|; a mix decomposes linearly.
TEST(ReflectField, TeTmDecomposition) {
  const Vec3 n = Vec3::UnitZ();
  const C eta = builtin_material("concrete")->complex_permittivity(kF);
  const Vec3 k = Vec3(std::sin(0.7), 0.0, -std::cos(0.7));
  const Vec3 kr = k - 2.0 * k.dot(n) * n;
  const FresnelCoefficients g = fresnel_reflection(eta, std::cos(0.7));
  const Vec3 s = n.cross(k).normalized();  // = ±y
  EXPECT_NEAR(std::abs(s.y()), 1.0, 1e-15);
  const CVec3 te = s.cast<C>();
  EXPECT_NEAR(cnorm(reflect_field(te, k, n, g) - g.te * te), 0.0, 1e-15);
  const CVec3 tm = s.cross(k).cast<C>();
  const CVec3 r_tm = reflect_field(tm, k, n, g);
  EXPECT_NEAR(cnorm(r_tm), std::abs(g.tm), 1e-14);
  EXPECT_NEAR(std::abs(r_tm(1)), 0.0, 1e-15);                    // in the plane of incidence (xz)
  EXPECT_NEAR(std::abs(kr.cast<C>().dot(r_tm)), 0.0, 1e-14);      // transverse to the reflected ray
  EXPECT_NEAR(cnorm(r_tm - g.tm * s.cross(kr).cast<C>()), 0.0, 1e-14);  // basis ŝ × k̂_r
  const CVec3 mix = C(0.3, 0.4) * te + C(-0.5, 0.2) * tm;
  EXPECT_NEAR(cnorm(reflect_field(mix, k, n, g) - (C(0.3, 0.4) * g.te * te + C(-0.5, 0.2) * r_tm)), 0.0, 1e-14);
  // Brewster: a TM wave on a lossless dielectric is not reflected at all.
  const double tb = brewster_angle_rad(4.0);
  const Vec3 kb(std::sin(tb), 0.0, -std::cos(tb));
  const CVec3 tmb = s.cross(kb).cast<C>();
  EXPECT_LT(cnorm(reflect_field(tmb, kb, n, fresnel_reflection(C(4.0, 0.0), std::cos(tb)))), 1e-12);
}

// A circularly polarized wave changes hand on a mirror: RHCP in → LHCP out (about the new direction).
TEST(ReflectField, CircularHandFlipsOnPec) {
  const Vec3 n = Vec3::UnitZ();
  const FresnelCoefficients pec{C(-1, 0), C(1, 0)};
  Polarization rhcp{PolarizationKind::kCircularRight, Vec3::UnitZ()};
  Polarization lhcp{PolarizationKind::kCircularLeft, Vec3::UnitZ()};
  for (const Vec3& k : incident_dirs()) {
    const Vec3 kr = k - 2.0 * k.dot(n) * n;
    const CVec3 r = reflect_field(rhcp.field(Quat::Identity(), k), k, n, pec);
    // |⟨e_LHCP(k_r), r⟩| = 1, |⟨e_RHCP(k_r), r⟩| = 0 (Hermitian inner product).
    EXPECT_NEAR(std::abs(lhcp.field(Quat::Identity(), kr).dot(r)), 1.0, 1e-12) << k.transpose();
    EXPECT_NEAR(std::abs(rhcp.field(Quat::Identity(), kr).dot(r)), 0.0, 1e-12) << k.transpose();
  }
}

TEST(TransmitField, AppliesTeAndTmThroughSlab) {
  const Vec3 n = Vec3::UnitX();
  const Vec3 k = Vec3(-std::cos(0.5), std::sin(0.5), 0.0);  // hits the x = const plane at 0.5 rad
  const C eta = builtin_material("brick")->complex_permittivity(kF);
  const FresnelCoefficients t = slab_transmission(eta, std::cos(0.5), 0.1, kF);
  const Vec3 s = n.cross(k).normalized();
  const CVec3 te = s.cast<C>(), tm = s.cross(k).cast<C>();
  EXPECT_NEAR(cnorm(transmit_field(te, k, n, t) - t.te * te), 0.0, 1e-15);
  EXPECT_NEAR(cnorm(transmit_field(tm, k, n, t) - t.tm * tm), 0.0, 1e-15);
  // Unit coefficients leave any transverse field unchanged; zero blocks it.
  const CVec3 e = transverse_field(k, 0.6, C(0, 0.8));
  EXPECT_NEAR(cnorm(transmit_field(e, k, n, {1.0, 1.0}) - e), 0.0, 1e-15);
  EXPECT_EQ(cnorm(transmit_field(e, k, n, material_transmission(*builtin_material("metal"), kF, 0.9))), 0.0);
  // At normal incidence a slab transmits every polarization alike.
  const FresnelCoefficients tn = slab_transmission(eta, 1.0, 0.1, kF);
  EXPECT_NEAR(std::abs(tn.te - tn.tm), 0.0, 1e-15);
  const CVec3 en = transverse_field(-n, 0.6, C(0, 0.8));
  EXPECT_NEAR(cnorm(transmit_field(en, -n, n, tn) - tn.te * en), 0.0, 1e-15);
}

}  // namespace
}  // namespace rfidray
