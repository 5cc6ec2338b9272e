// The tag antenna model (core/thin_wire_dipole.h, core/tag_antenna.h) against closed forms and against NEC-2
// (nec2c, run here: the reference is computed, not pasted).
//
// The NEC-2 reference and its own error: a thin dipole (0.166 m, radius 0.5 mm, 866 MHz) parallel to a
// perfectly conducting ground (GN 1) at height d. NEC-2's thin-wire kernel wants segments longer than ~8 radii;
// the reference is its 41-segment solution (Δ/a = 8.1), its own error the largest difference to the 21-segment
// (Δ/a = 16) and to the 81-segment extended-kernel (Δ/a = 4, EK) solutions. Near resonance beside metal (5 mm–
// 1 cm) that error is 0.8–1 Ω of reactance on an |Z| of 2–9 Ω, so the impedance is held to 10 % of |Z_NEC| plus
// NEC-2's own error; the power transfer τ, which is what a link sees, to 1 dB as the issue asks.
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <sstream>
#include <string>

#include "core/error.h"
#include "core/material.h"
#include "core/tag_antenna.h"
#include "core/thin_wire_dipole.h"
#include "core/units.h"
#include "tests/support/run_command.h"
#include "tests/support/scratch_dir.h"

namespace rfidray {
namespace {

using testing::ScratchDir;

constexpr double kLength_m = 0.166, kRadius_m = 0.0005, kFrequency_hz = 866e6;

TagAntennaSpec dipole_tag(double conductivity_s_m = 0.0) {
  TagAntennaSpec a;
  a.kind = TagAntennaSpec::Kind::kDipole;
  a.dipole = {kLength_m, kRadius_m, conductivity_s_m};
  return a;
}

double db(double v) { return 10.0 * std::log10(v); }

const RadioMaterial& metal() {
  static const RadioMaterial m = *builtin_material("metal");
  return m;
}

// --- NEC-2 through nec2c ---------------------------------------------------------------------------------------

std::string nec2c_path() {
#ifdef RFIDRAY_NEC2C
  return RFIDRAY_NEC2C;
#else
  return "";
#endif
}

// Skips where nec2c is not installed, except under CI, which installs it (.ci/install-deps): there it fails.
#define REQUIRE_NEC2C()                                                                             \
  do {                                                                                              \
    if (nec2c_path().empty()) {                                                                     \
      if (std::getenv("CI")) FAIL() << "nec2c not found (apt-get install nec2c; .ci/install-deps)"; \
      GTEST_SKIP() << "nec2c not installed (apt-get install nec2c)";                                \
    }                                                                                               \
  } while (0)

struct NecDeck {
  int segments = 41;
  double height_m = 0.0;  // ≤ 0: free space
  bool extended_kernel = false;
  double conductivity_s_m = 0.0;
  // Plane wave at normal incidence (E along the wire) into a load at the feed instead of a voltage source.
  bool plane_wave = false;
  std::complex<double> load_ohm;
  // A lossy half-space instead of a perfect ground (GN 2: NEC-2's Sommerfeld solution), ε' and σ (S/m).
  double ground_permittivity = 0.0;  // 0: perfect ground
  double ground_conductivity_s_m = 0.0;
};

std::string deck_text(const NecDeck& d) {
  std::ostringstream s;
  s.precision(10);
  const double z = d.height_m > 0.0 ? d.height_m : 1.0;  // free space: the height is irrelevant
  s << "CM rfidray test: thin dipole parallel to a perfect ground\nCE\n";
  s << "GW 1 " << d.segments << " 0 " << -kLength_m / 2 << " " << z << " 0 " << kLength_m / 2 << " " << z << " "
    << kRadius_m << "\nGE " << (d.height_m > 0.0 ? 1 : 0) << "\n";
  if (d.extended_kernel) s << "EK\n";
  if (d.height_m <= 0.0)
    s << "GN -1\n";
  else if (d.ground_permittivity > 0.0)
    s << "GN 2 0 0 0 " << d.ground_permittivity << " " << d.ground_conductivity_s_m << "\n";
  else
    s << "GN 1\n";
  const int feed = (d.segments + 1) / 2;
  if (d.conductivity_s_m > 0.0) s << "LD 5 1 1 " << d.segments << " " << d.conductivity_s_m << "\n";
  if (d.plane_wave) {
    s << "LD 4 1 " << feed << " " << feed << " " << d.load_ohm.real() << " " << d.load_ohm.imag() << "\n";
    // Incidence from the zenith (θ = 0), φ = 90°: E along θ̂ = ŷ, the wire's direction.
    s << "EX 1 1 1 0 0.0 90.0 0.0\n";
  } else {
    s << "EX 0 1 " << feed << " 0 1.0 0.0\n";
  }
  s << "FR 0 1 0 0 " << kFrequency_hz / 1e6 << " 0\n";
  // With a plane wave: the field the structure scatters back toward the zenith (the reader), 1 km away.
  s << (d.plane_wave ? "RP 0 1 1 1000 0.0 90.0 0.0 0.0\nEN\n" : "XQ\nEN\n");
  return s.str();
}

// Runs nec2c on the deck; returns its output text (empty on failure).
std::string run_nec(const ScratchDir& dir, const NecDeck& d, const std::string& name) {
  const auto in = dir.write(name + ".nec", deck_text(d));
  const auto out = dir / (name + ".out");
  const auto r = testing::run_command("'" + nec2c_path() + "' -i '" + in.string() + "' -o '" + out.string() + "'");
  if (r.status != 0) return "";
  return testing::slurp(out);
}

// The feed's impedance from "ANTENNA INPUT PARAMETERS" (columns: tag seg Vr Vi Ir Ii Zr Zi ...).
std::optional<std::complex<double>> nec_impedance(const ScratchDir& dir, const NecDeck& d, const std::string& name) {
  const std::string out = run_nec(dir, d, name);
  const size_t at = out.find("ANTENNA INPUT PARAMETERS");
  if (at == std::string::npos) return std::nullopt;
  std::istringstream s(out.substr(at));
  std::string line;
  for (int i = 0; i < 4 && std::getline(s, line); ++i) {
  }
  std::istringstream row(line);
  int tag = 0, seg = 0;
  double vr, vi, ir, ii, zr, zi;
  if (!(row >> tag >> seg >> vr >> vi >> ir >> ii >> zr >> zi)) return std::nullopt;
  return std::complex<double>(zr, zi);
}

// |current| on the feed segment from "CURRENTS AND LOCATION" (columns: seg tag x y z len Ir Ii |I| phase).
std::optional<double> nec_feed_current(const ScratchDir& dir, const NecDeck& d, const std::string& name) {
  const std::string out = run_nec(dir, d, name);
  const size_t at = out.find("CURRENTS AND LOCATION");
  if (at == std::string::npos) return std::nullopt;
  std::istringstream s(out.substr(at));
  std::string line;
  const int feed = (d.segments + 1) / 2;
  while (std::getline(s, line)) {
    std::istringstream row(line);
    int seg = 0, tag = 0;
    double x, y, z, len, ir, ii, mag;
    if ((row >> seg >> tag >> x >> y >> z >> len >> ir >> ii >> mag) && seg == feed) return mag;
  }
  return std::nullopt;
}

// E_θ scattered back toward the zenith, from "RADIATION PATTERNS" (the row θ = 0: columns θ φ Gv Gh Gt axial tilt
// sense |Eθ| arg Eθ |Eφ| arg Eφ).
std::optional<std::complex<double>> nec_backscatter(const ScratchDir& dir, const NecDeck& d, const std::string& name) {
  const std::string out = run_nec(dir, d, name);
  const size_t at = out.find("RADIATION PATTERNS");
  if (at == std::string::npos) return std::nullopt;
  std::istringstream s(out.substr(at));
  std::string line;
  while (std::getline(s, line)) {
    std::istringstream row(line);
    double theta, phi, gv, gh, gt, axial, tilt, mag, arg_deg;
    std::string sense;
    if ((row >> theta >> phi >> gv >> gh >> gt >> axial >> tilt >> sense >> mag >> arg_deg) && theta == 0.0)
      return std::polar(mag, arg_deg * kPi / 180.0);
  }
  return std::nullopt;
}

double power_transfer(std::complex<double> z_antenna, std::complex<double> z_chip) {
  return 4.0 * z_chip.real() * z_antenna.real() / std::norm(z_antenna + z_chip);
}

// --- against NEC-2 -------------------------------------------------------------------------------------------------

TEST(TagAntennaNec, DipoleImpedanceAndPowerTransferBesideMetalMatchNec2) {
  REQUIRE_NEC2C();
  ScratchDir dir("tag_antenna_nec");
  const auto z_free_nec = nec_impedance(dir, {.segments = 41}, "free");
  ASSERT_TRUE(z_free_nec) << deck_text({.segments = 41});
  const TagAntennaSpec tag = dipole_tag();
  const std::complex<double> z_free = antenna_free_space_impedance(tag, kFrequency_hz);
  EXPECT_LE(std::abs(z_free - *z_free_nec), 0.10 * std::abs(*z_free_nec))
      << "free space: rfidray " << z_free << ", NEC-2 " << *z_free_nec;

  for (double d : {0.003, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2}) {
    const std::string h = std::to_string(d);
    const auto ref = nec_impedance(dir, {.segments = 41, .height_m = d}, "h41_" + h);
    const auto coarse = nec_impedance(dir, {.segments = 21, .height_m = d}, "h21_" + h);
    const auto fine = nec_impedance(dir, {.segments = 81, .height_m = d, .extended_kernel = true}, "h81_" + h);
    ASSERT_TRUE(ref && coarse && fine) << "nec2c failed at d = " << d;
    const double nec_error = std::max(std::abs(*ref - *coarse), std::abs(*ref - *fine));
    const std::complex<double> z = antenna_impedance_in_place(tag, &metal(), d, kFrequency_hz);
    EXPECT_LE(std::abs(z - *ref), 0.10 * std::abs(*ref) + nec_error)
        << "d = " << d << " m: rfidray " << z << ", NEC-2 " << *ref << " (NEC-2's own error " << nec_error << " Ω)";
    // τ with the chip conjugate-matched to each code's own free-space impedance (the table).
    const double tau = power_transfer(z, std::conj(z_free));
    const double tau_nec = power_transfer(*ref, std::conj(*z_free_nec));
    EXPECT_NEAR(db(tau), db(tau_nec), 1.0) << "d = " << d << " m";
    const TagCoupling c = tag_coupling(tag, TagChipSpec{}, &metal(), d, kFrequency_hz);
    EXPECT_NEAR(c.power_transfer, tau, 1e-12 + 1e-9 * tau);
  }
}

// A dielectric half-space behind the dipole (core/dielectric_half_space.h) against NEC-2's Sommerfeld ground
// (GN 2, which NEC-2 computes by numerical Sommerfeld integration and interpolation, the same physics by an
// independent route): water (the builtin's Debye fit at 866 MHz) and a low-loss ε = 2 (cardboard, wood), from
// 3 mm to 20 cm. Tolerances as beside metal: 10 % of |Z_NEC| plus NEC-2's own 41-vs-21-segment difference,
// and τ to 1 dB. (Measured: within 4 %; the offset is the 2–3 Ω of reactance the two codes already differ by in
// free space.)
TEST(TagAntennaNec, DipoleBesideDielectricHalfSpaceMatchesNec2Sommerfeld) {
  REQUIRE_NEC2C();
  ScratchDir dir("tag_antenna_nec_dielectric");
  const auto z_free_nec = nec_impedance(dir, {.segments = 41}, "free");
  ASSERT_TRUE(z_free_nec);
  const TagAntennaSpec tag = dipole_tag();
  const std::complex<double> z_free = antenna_free_space_impedance(tag, kFrequency_hz);
  for (const RadioMaterial& material : {*builtin_material("water"), user_material("eps2", 2.0, 0.005, 0.0)}) {
    const std::complex<double> eps = material.complex_permittivity(kFrequency_hz);
    const double sigma_s_m = material.conductivity_s_m(kFrequency_hz);
    for (double d : {0.003, 0.01, 0.05, 0.2}) {
      const std::string name = material.name + "_" + std::to_string(d);
      NecDeck deck{.segments = 41, .height_m = d, .ground_permittivity = eps.real(), .ground_conductivity_s_m = sigma_s_m};
      const auto ref = nec_impedance(dir, deck, "d41_" + name);
      deck.segments = 21;
      const auto coarse = nec_impedance(dir, deck, "d21_" + name);
      ASSERT_TRUE(ref && coarse) << "nec2c failed: " << deck_text(deck);
      const double nec_error = std::abs(*ref - *coarse);
      const std::complex<double> z = antenna_impedance_in_place(tag, &material, d, kFrequency_hz);
      EXPECT_LE(std::abs(z - *ref), 0.10 * std::abs(*ref) + nec_error)
          << material.name << " at d = " << d << " m: rfidray " << z << ", NEC-2 " << *ref << " (own error "
          << nec_error << " Ω)";
      EXPECT_NEAR(db(power_transfer(z, std::conj(z_free))), db(power_transfer(*ref, std::conj(*z_free_nec))), 1.0)
          << material.name << " at d = " << d << " m";
      // Nearer than a perfect conductor at the same distance would be, never as detuned.
      if (d <= 0.01)
        EXPECT_GT(power_transfer(z, std::conj(z_free)),
                  power_transfer(antenna_impedance_in_place(tag, &metal(), d, kFrequency_hz), std::conj(z_free)));
    }
  }
}

// The whole receive chain beside metal, not only the impedance: NEC-2 illuminates the dipole over ground with a
// plane wave at normal incidence, the feed loaded by the chip (conjugate of NEC-2's free-space impedance); the
// chip's power against free space is |I_d|² / |I_free|². rfidray splits it into the image path
// (backing_image_factor, |1 − e^{−j2kd}|²) times F = 4 R_a0 R_c / |Z_a + Z_c|² (core/tag_antenna.h).
TEST(TagAntennaNec, ChipPowerBesideMetalUnderAPlaneWaveMatchesNec2) {
  REQUIRE_NEC2C();
  ScratchDir dir("tag_antenna_nec_pw");
  const auto z_free_nec = nec_impedance(dir, {.segments = 41}, "free");
  ASSERT_TRUE(z_free_nec);
  const std::complex<double> load = std::conj(*z_free_nec);
  const auto i_free = nec_feed_current(dir, {.segments = 41, .plane_wave = true, .load_ohm = load}, "pw_free");
  ASSERT_TRUE(i_free);
  const TagAntennaSpec tag = dipole_tag();
  TagBackingSpec backing{TagBackingSpec::Kind::kGiven, *builtin_material("metal"), 0.0};
  for (double d : {0.003, 0.005, 0.01, 0.02, 0.05, 0.1}) {
    const auto i_d = nec_feed_current(dir, {.segments = 41, .height_m = d, .plane_wave = true, .load_ohm = load},
                                      "pw_" + std::to_string(d));
    ASSERT_TRUE(i_d);
    const double nec_db = 20.0 * std::log10(*i_d / *i_free);
    backing.distance_m = d;
    const double image = std::norm(backing_image_factor(backing, 1.0, kFrequency_hz));
    const TagCoupling c = tag_coupling(tag, TagChipSpec{}, &metal(), d, kFrequency_hz);
    const double rfidray_db = db(image * c.chip_power_factor);
    EXPECT_NEAR(rfidray_db, nec_db, 1.0) << "d = " << d << " m (image path alone: " << db(image) << " dB)";
  }
}

// The same receive chain beside water and beside a low-loss ε = 2: NEC-2's plane wave over its Sommerfeld ground
// (the incident field there includes the Fresnel-reflected wave) against rfidray's |1 + Γ e^{−j2kd}|² · F. The
// split assumes the open-circuited antenna barely scatters, which NEC-2 checks here.
TEST(TagAntennaNec, ChipPowerBesideDielectricUnderAPlaneWaveMatchesNec2) {
  REQUIRE_NEC2C();
  ScratchDir dir("tag_antenna_nec_pw_dielectric");
  const auto z_free_nec = nec_impedance(dir, {.segments = 41}, "free");
  ASSERT_TRUE(z_free_nec);
  const std::complex<double> load = std::conj(*z_free_nec);
  const auto i_free = nec_feed_current(dir, {.segments = 41, .plane_wave = true, .load_ohm = load}, "pw_free");
  ASSERT_TRUE(i_free);
  const TagAntennaSpec tag = dipole_tag();
  for (const RadioMaterial& material : {*builtin_material("water"), user_material("eps2", 2.0, 0.005, 0.0)}) {
    TagBackingSpec backing{TagBackingSpec::Kind::kGiven, material, 0.0};
    for (double d : {0.003, 0.01, 0.05, 0.1}) {
      const NecDeck deck{.segments = 41, .height_m = d, .plane_wave = true, .load_ohm = load,
                         .ground_permittivity = material.complex_permittivity(kFrequency_hz).real(),
                         .ground_conductivity_s_m = material.conductivity_s_m(kFrequency_hz)};
      const auto i_d = nec_feed_current(dir, deck, "pw_" + material.name + std::to_string(d));
      ASSERT_TRUE(i_d) << deck_text(deck);
      const double nec_db = 20.0 * std::log10(*i_d / *i_free);
      backing.distance_m = d;
      const double image = std::norm(backing_image_factor(backing, 1.0, kFrequency_hz));
      const TagCoupling c = tag_coupling(tag, TagChipSpec{}, &material, d, kFrequency_hz);
      EXPECT_NEAR(db(image * c.chip_power_factor), nec_db, 1.0)
          << material.name << " at d = " << d << " m (reflection alone: " << db(image) << " dB)";
    }
  }
}

// The modulated backscatter beside metal: NEC-2 scatters the plane wave off the dipole over ground with the chip
// load and with a short (the two modulation states); the modulated field is their difference, against the same
// in free space. rfidray: |image|⁴ · K / K_free (K = (R_a0/R_a)² |ρ_1 − ρ_2|² / 4). Near resonance of the shorted
// state (1 cm) the shorted current follows 1/|Z_a| with |Z_a| ≈ 2 Ω, so NEC-2's own reactance error moves it by
// decibels: the tolerance is 1 dB plus NEC-2's own difference between 41 and 21 segments.
TEST(TagAntennaNec, ModulatedBackscatterBesideMetalMatchesNec2) {
  REQUIRE_NEC2C();
  ScratchDir dir("tag_antenna_nec_bs");
  const auto z_free_nec = nec_impedance(dir, {.segments = 41}, "free");
  ASSERT_TRUE(z_free_nec);
  const std::complex<double> chip = std::conj(*z_free_nec), shorted(1e-9, 0.0);
  const auto modulated_db = [&](int segments, double d) -> std::optional<double> {
    const auto a = nec_backscatter(dir, {.segments = segments, .height_m = d, .plane_wave = true, .load_ohm = chip},
                                   "bs_a" + std::to_string(segments) + "_" + std::to_string(d));
    const auto b = nec_backscatter(dir, {.segments = segments, .height_m = d, .plane_wave = true, .load_ohm = shorted},
                                   "bs_b" + std::to_string(segments) + "_" + std::to_string(d));
    const auto fa = nec_backscatter(dir, {.segments = segments, .plane_wave = true, .load_ohm = chip},
                                    "bs_fa" + std::to_string(segments));
    const auto fb = nec_backscatter(dir, {.segments = segments, .plane_wave = true, .load_ohm = shorted},
                                    "bs_fb" + std::to_string(segments));
    if (!(a && b && fa && fb)) return std::nullopt;
    return 20.0 * std::log10(std::abs(*a - *b) / std::abs(*fa - *fb));
  };
  const TagAntennaSpec tag = dipole_tag();
  const TagCoupling free = tag_coupling(tag, TagChipSpec{}, nullptr, 0.0, kFrequency_hz);
  TagBackingSpec backing{TagBackingSpec::Kind::kGiven, *builtin_material("metal"), 0.0};
  for (double d : {0.003, 0.005, 0.01, 0.02, 0.05, 0.1}) {
    const auto nec = modulated_db(41, d);
    const auto nec_coarse = modulated_db(21, d);
    ASSERT_TRUE(nec && nec_coarse) << "nec2c failed at d = " << d;
    backing.distance_m = d;
    const double image2 = std::norm(backing_image_factor(backing, 1.0, kFrequency_hz));
    const TagCoupling c = tag_coupling(tag, TagChipSpec{}, &metal(), d, kFrequency_hz);
    const double rfidray_db = db(image2 * image2 * c.modulation_factor / free.modulation_factor);
    EXPECT_NEAR(rfidray_db, *nec, 1.0 + std::abs(*nec - *nec_coarse)) << "d = " << d << " m";
  }
}

// Skin-effect loss of an aluminium wire: beside metal the loss resistance is comparable to the radiation
// resistance. NEC-2's LD 5 (wire conductivity) is the reference.
TEST(TagAntennaNec, WireConductivityLossMatchesNec2) {
  REQUIRE_NEC2C();
  ScratchDir dir("tag_antenna_nec_loss");
  const TagAntennaSpec tag = dipole_tag(3.5e7);
  for (double d : {0.003, 0.01}) {
    const auto ref = nec_impedance(dir, {.segments = 41, .height_m = d, .conductivity_s_m = 3.5e7},
                                   "loss_" + std::to_string(d));
    const auto lossless = nec_impedance(dir, {.segments = 41, .height_m = d}, "lossless_" + std::to_string(d));
    ASSERT_TRUE(ref && lossless);
    const std::complex<double> z = antenna_impedance_in_place(tag, &metal(), d, kFrequency_hz);
    const std::complex<double> z0 = antenna_impedance_in_place(dipole_tag(), &metal(), d, kFrequency_hz);
    // The loss resistance (the rise of R) within 10 % of NEC-2's.
    EXPECT_NEAR(z.real() - z0.real(), ref->real() - lossless->real(), 0.10 * (ref->real() - lossless->real()))
        << "d = " << d;
  }
}

// --- closed forms and self-consistency --------------------------------------------------------------------------

TEST(TagAntenna, MatchedTagInFreeSpaceReadsAsWithoutTheModel) {
  const TagCoupling c = tag_coupling(dipole_tag(), TagChipSpec{}, nullptr, 0.0, kFrequency_hz);
  EXPECT_NEAR(c.power_transfer, 1.0, 1e-12);
  EXPECT_NEAR(c.chip_power_factor, 1.0, 1e-12);
  EXPECT_NEAR(c.modulation_factor, 0.25, 1e-12);  // |0 − (−Z*/Z)|² / 4
  EXPECT_NEAR(c.backscatter_phase_rad, 0.0, 1e-12);
}

TEST(TagAntenna, ChipImpedancesAreTheirCircuits) {
  const double w = kTwoPi * kFrequency_hz;
  const TagChipSpec series{TagChipSpec::Kind::kSeries, 20.0, 1e-12};
  const std::complex<double> zs = chip_impedance(series, dipole_tag(), kFrequency_hz);
  EXPECT_DOUBLE_EQ(zs.real(), 20.0);
  EXPECT_NEAR(zs.imag(), -1.0 / (w * 1e-12), 1e-9);
  const TagChipSpec parallel{TagChipSpec::Kind::kParallel, 1500.0, 1e-12};
  const std::complex<double> zp = chip_impedance(parallel, dipole_tag(), kFrequency_hz);
  const std::complex<double> expect = 1.0 / std::complex<double>(1.0 / 1500.0, w * 1e-12);
  EXPECT_NEAR(std::abs(zp - expect), 0.0, 1e-9);
  // τ of a badly matched chip in free space is below one; F equals τ there (Z_a = Z_a0).
  const TagCoupling c = tag_coupling(dipole_tag(), series, nullptr, 0.0, kFrequency_hz);
  EXPECT_LT(c.power_transfer, 0.5);
  EXPECT_NEAR(c.chip_power_factor, c.power_transfer, 1e-12);
}

TEST(TagAntenna, MountImageFactorIsTheImagePairAndBlocksBehind) {
  const double lambda = wavelength_m(kFrequency_hz);
  TagBackingSpec m{TagBackingSpec::Kind::kGiven, *builtin_material("metal"), lambda / 4.0};
  // d = λ/4 at normal incidence: the image wave arrives in phase, |AF| = 2.
  EXPECT_NEAR(std::abs(backing_image_factor(m, 1.0, kFrequency_hz)), 2.0, 1e-12);
  EXPECT_EQ(backing_image_factor(m, -0.3, kFrequency_hz), std::complex<double>(0.0, 0.0));
  EXPECT_EQ(backing_image_factor(m, 0.0, kFrequency_hz), std::complex<double>(0.0, 0.0));
  m.distance_m = 0.01;
  const double kd = wavenumber_rad_m(kFrequency_hz) * 0.01;
  EXPECT_NEAR(std::abs(backing_image_factor(m, 1.0, kFrequency_hz)), 2.0 * std::sin(kd), 1e-12);
  m.kind = TagBackingSpec::Kind::kScene;  // a meshed surface: the ray tracer's image, not the backing's
  EXPECT_EQ(backing_image_factor(m, 1.0, kFrequency_hz), std::complex<double>(1.0, 0.0));
}

TEST(TagAntenna, ImpedanceConvergesWithSegments) {
  const ThinWireDipole d{kLength_m, kRadius_m};
  const int n = default_dipole_segments(d);
  const auto plane = perfect_conductor_plane(0.003, kFrequency_hz);
  const std::complex<double> z = dipole_input_impedance(d, kFrequency_hz, plane.get());
  const std::complex<double> z2 = dipole_input_impedance(d, kFrequency_hz, plane.get(), 2 * n);
  EXPECT_LE(std::abs(z - z2), 0.05 * std::abs(z2)) << z << " vs " << z2 << " at " << 2 * n << " segments";
  const std::complex<double> f = dipole_input_impedance(d, kFrequency_hz);
  const std::complex<double> f2 = dipole_input_impedance(d, kFrequency_hz, nullptr, 2 * n);
  EXPECT_LE(std::abs(f - f2), 0.01 * std::abs(f2));
  // Far from the plane the image couples through its radiated field only, which falls as 1/distance: the
  // impedance change at 6 m is half that at 3 m (within 10 %), about an ohm.
  const auto at3 = perfect_conductor_plane(3.0, kFrequency_hz);
  const auto at6 = perfect_conductor_plane(6.0, kFrequency_hz);
  const double dz3 = std::abs(dipole_input_impedance(d, kFrequency_hz, at3.get()) - f);
  const double dz6 = std::abs(dipole_input_impedance(d, kFrequency_hz, at6.get()) - f);
  EXPECT_LT(dz3, 2.0);
  EXPECT_NEAR(dz6 / dz3, 0.5, 0.05) << dz3 << " Ω at 3 m, " << dz6 << " Ω at 6 m";
}

TEST(TagAntenna, BadParametersNameTheirField) {
  TagAntennaSpec a = dipole_tag();
  a.dipole.radius_m = 0.05;
  try {
    validate(a, TagChipSpec{}, TagBackingSpec{}, "tags[2]");
    FAIL() << "a fat wire was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tags[2].antenna.radius_m"), std::string::npos) << e.what();
  }
  try {
    backing_material("cheese", "tags[0].backing.material");
    FAIL() << "an unknown backing material was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tags[0].backing.material"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("water"), std::string::npos) << e.what();  // names the known ones
  }
  const TagBackingSpec too_close{TagBackingSpec::Kind::kGiven, *builtin_material("metal"), 1e-4};
  EXPECT_THROW(validate(dipole_tag(), TagChipSpec{}, too_close, "t"), InputError);
  EXPECT_THROW(dipole_input_impedance({kLength_m, kRadius_m}, -1.0), InputError);
  EXPECT_THROW(dipole_input_impedance({kLength_m, kRadius_m}, kFrequency_hz, nullptr, 7), InputError);
}

}  // namespace
}  // namespace rfidray
