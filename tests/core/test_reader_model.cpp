// Reader models: the paper's eq. 3–5 and the physical (channel-based) model.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <complex>
#include <string>
#include <vector>

#include "core/channel.h"
#include "core/distribution.h"
#include "core/error.h"
#include "core/reader_model.h"
#include "core/units.h"

namespace rfidray {
namespace {

// A reader with every noise source switched off and no quantization.
ReaderParams noiseless_paper() {
  ReaderParams r;
  r.noise_phi_rad = 0.0;
  r.noise_rssi = 0.0;
  r.noise_rssi_db = 0.0;
  r.range_sigma = 0.0;
  r.phase_bits = 0;
  r.rssi_resolution_db = 0.0;
  r.communication_gain = 1.0;
  r.range_m = 7.0;
  return r;
}

LinkState link_at(double d, double f = 865.7e6, double phi0 = 0.0) {
  LinkState l;
  l.distance_m = d;
  l.frequency_hz = f;
  l.phase_offset_rad = phi0;
  return l;
}

double normal_cdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

// ---- eq. 3–5, hand-computed -------------------------------------------------------------------
// D = 2 m, f = 865.7 MHz: λ = c/f = 299792458 / 865.7e6 = 0.34630063301 m.
// 4πD/λ = 8π / 0.34630063301 = 72.574921420 rad = 11.5506575 turns → mod 2π = 72.574921420 − 11·2π
//       = 3.4598830412 rad.
// λ/(4πD) = 0.34630063301 / 25.132741229 = 0.0137788644; 40·log10(0.0137788644) = 40·(−1.8607866) = −74.431463.
TEST(PaperModel, ZeroNoiseMatchesEq4And5Exactly) {
  const ReaderParams r = noiseless_paper();
  Rng rng(1);
  const Reading rd = paper_reading(r, link_at(2.0), rng);
  ASSERT_TRUE(rd.read);
  const double lambda = kSpeedOfLight_m_s / 865.7e6;
  EXPECT_NEAR(lambda, 0.34630063301, 1e-11);
  EXPECT_DOUBLE_EQ(rd.phase_rad, wrap_to_2pi(4.0 * kPi * 2.0 / lambda));
  EXPECT_NEAR(rd.phase_rad, 3.4598830412, 1e-10);
  EXPECT_DOUBLE_EQ(rd.rssi_dbm, 40.0 * std::log10(lambda / (4.0 * kPi * 2.0)));
  EXPECT_NEAR(rd.rssi_dbm, -74.431463, 1e-6);
}

// Default quantization: RSSI round(−74.431463) = −74 dB (1 dB) or −74.5 (0.5 dB); phase to 12 bits:
// 3.4598830412 / (2π/4096) = 2255.46 → level 2255 → 2255·2π/4096 = 3.4591266767 rad.
// Communication gain G_RT = 3: 40·log10(3·0.0137788644) = −55.346613 → −55.
TEST(PaperModel, QuantizedOutputsAndCommunicationGain) {
  ReaderParams r = noiseless_paper();
  r.phase_bits = 12;
  r.rssi_resolution_db = 1.0;
  Rng rng(1);
  Reading rd = paper_reading(r, link_at(2.0), rng);
  ASSERT_TRUE(rd.read);
  EXPECT_DOUBLE_EQ(rd.rssi_dbm, -74.0);
  EXPECT_DOUBLE_EQ(rd.phase_rad, 2255.0 * kTwoPi / 4096.0);
  EXPECT_NEAR(rd.phase_rad, 3.4591266767, 1e-10);
  r.rssi_resolution_db = 0.5;
  rd = paper_reading(r, link_at(2.0), rng);
  EXPECT_DOUBLE_EQ(rd.rssi_dbm, -74.5);
  r.rssi_resolution_db = 1.0;
  r.communication_gain = 3.0;
  rd = paper_reading(r, link_at(2.0), rng);
  EXPECT_DOUBLE_EQ(rd.rssi_dbm, -55.0);
}

// φ0 = 1 rad shifts the phase: 3.4598830412 + 1 = 4.4598830412; φ0 = 3 rad wraps: 6.4598830412 − 2π = 0.1766977340.
TEST(PaperModel, PhaseOffsetAddsAndWraps) {
  const ReaderParams r = noiseless_paper();
  Rng rng(1);
  EXPECT_NEAR(paper_reading(r, link_at(2.0, 865.7e6, 1.0), rng).phase_rad, 4.4598830412, 1e-10);
  EXPECT_NEAR(paper_reading(r, link_at(2.0, 865.7e6, 3.0), rng).phase_rad, 0.1766977340, 1e-10);
}

TEST(PaperModel, PhaseNoiseHasConfiguredSigma) {
  ReaderParams r = noiseless_paper();
  r.noise_phi_rad = 0.1;
  Rng rng = make_stream(3, {0});
  const double truth = wrap_to_2pi(4.0 * kPi * 2.0 / wavelength_m(865.7e6));
  const int n = 20000;
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    const double e = wrap_to_pi(paper_reading(r, link_at(2.0), rng).phase_rad - truth);
    s += e;
    s2 += e * e;
  }
  const double mean = s / n, sd = std::sqrt(s2 / n - mean * mean);
  // se(mean) = σ/√N = 7.1e-4; se(sd) ≈ σ/√(2N) = 5.0e-4; 6σ bands.
  EXPECT_NEAR(mean, 0.0, 6 * 0.1 / std::sqrt(n));
  EXPECT_NEAR(sd, 0.1, 6 * 0.1 / std::sqrt(2.0 * n));
}

// eq. 5 noise is added to the linear amplitude: 10^(RSSI/40) = λ/(4πD) + n_RSSI.
TEST(PaperModel, RssiNoiseIsAddedToTheAmplitude) {
  ReaderParams r = noiseless_paper();
  r.noise_rssi = 0.001;
  Rng rng = make_stream(4, {0});
  const double a = wavelength_m(865.7e6) / (4.0 * kPi * 2.0);
  const int n = 20000;
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    const Reading rd = paper_reading(r, link_at(2.0), rng);
    ASSERT_TRUE(rd.read);
    const double e = std::pow(10.0, rd.rssi_dbm / 40.0) - a;
    s += e;
    s2 += e * e;
  }
  const double mean = s / n, sd = std::sqrt(s2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 6 * 0.001 / std::sqrt(n));
  EXPECT_NEAR(sd, 0.001, 6 * 0.001 / std::sqrt(2.0 * n));
}

// When the noise drives G_RT·λ/(4πD) + n_RSSI ≤ 0, eq. 5 is undefined: no read, never NaN.
// With σ = 1 ≫ a = 0.0137788644 the read fraction is P(a + N(0,1) > 0) = Φ(a) = 0.50550.
TEST(PaperModel, NonPositiveLogArgumentIsNoRead) {
  ReaderParams r = noiseless_paper();
  r.noise_rssi = 1.0;
  Rng rng = make_stream(5, {0});
  const double a = wavelength_m(865.7e6) / (4.0 * kPi * 2.0);
  const int n = 20000;
  int reads = 0;
  for (int i = 0; i < n; ++i) {
    const Reading rd = paper_reading(r, link_at(2.0), rng);
    if (rd.read) {
      ++reads;
      ASSERT_TRUE(std::isfinite(rd.rssi_dbm));
    }
  }
  const double p = normal_cdf(a);
  EXPECT_NEAR(double(reads) / n, p, 6 * std::sqrt(p * (1 - p) / n));
  EXPECT_LT(reads, n);  // some attempts must have been dropped
}

// Read iff D ≤ r·|1 + n_r|, n_r ~ N(0, σ²). At D = r(1 + x): P(read) = P(|1 + n_r| ≥ 1 + x)
// = Q(x/σ) + Φ((−2 − x)/σ) (the second term is ~0 for σ = 0.05). Checked within 6 binomial standard errors.
TEST(PaperModel, RangePerturbationStatistics) {
  ReaderParams r = noiseless_paper();
  r.range_sigma = 0.05;
  r.range_m = 5.0;
  const int n = 20000;
  for (double x : {-0.08, -0.03, 0.0, 0.05, 0.1}) {
    Rng rng = make_stream(6, {uint64_t((x + 1) * 1000)});
    int reads = 0;
    for (int i = 0; i < n; ++i) reads += paper_reading(r, link_at(r.range_m * (1 + x)), rng).read;
    const double p = (1.0 - normal_cdf(x / 0.05)) + normal_cdf((-2.0 - x) / 0.05);
    EXPECT_NEAR(double(reads) / n, p, 6 * std::sqrt(p * (1 - p) / n) + 1e-12) << "x = " << x;
  }
}

TEST(PaperModel, SharpRangeWithoutPerturbation) {
  const ReaderParams r = noiseless_paper();  // range 7 m, σ_r = 0
  Rng rng(1);
  EXPECT_TRUE(paper_reading(r, link_at(7.0), rng).read);
  EXPECT_FALSE(paper_reading(r, link_at(7.0 + 1e-9), rng).read);
}

TEST(PaperModel, OptionalDistributionShiftsPhase) {
  ReaderParams r = noiseless_paper();
  // uniform [0.5, 0.5 + 1e-12): n_opt ≈ 0.5 on every draw
  r.optional_distribution = parse_distribution("uniform", {0.5, 0.5 + 1e-12}, "f");
  Rng rng(1);
  const double truth = wrap_to_2pi(4.0 * kPi * 2.0 / wavelength_m(865.7e6) + 0.5);
  EXPECT_NEAR(paper_reading(r, link_at(2.0), rng).phase_rad, truth, 1e-9);
}

// Every draw is made on every attempt, so a read and a no-read leave the stream at the same position.
TEST(PaperModel, StreamPositionIndependentOfOutcome) {
  ReaderParams r;  // default noise
  Rng a = make_stream(9, {1}), b = make_stream(9, {1});
  EXPECT_TRUE(paper_reading(r, link_at(1.0), a).read);
  EXPECT_FALSE(paper_reading(r, link_at(50.0), b).read);
  EXPECT_EQ(a(), b());
  r.model = ReaderModelKind::kPhysical;
  TagParams tag;
  LinkState strong = link_at(1.0), weak = link_at(1.0);
  strong.h_one_way = {0.01, 0.0};
  weak.h_one_way = {1e-6, 0.0};
  EXPECT_TRUE(read_tag(r, tag, strong, a).read);
  EXPECT_FALSE(read_tag(r, tag, weak, b).read);
  EXPECT_EQ(a(), b());
}

TEST(ReaderModel, SameSeedSameReadings) {
  ReaderParams r;
  r.optional_distribution = parse_distribution("gamma", {2.0, 0.1}, "f");
  Rng a = make_stream(11, {2, 3}), b = make_stream(11, {2, 3});
  for (int i = 0; i < 200; ++i) {
    const LinkState l = link_at(1.0 + 0.03 * i);
    const Reading x = paper_reading(r, l, a), y = paper_reading(r, l, b);
    EXPECT_EQ(x.read, y.read);
    EXPECT_EQ(x.phase_rad, y.phase_rad);
    EXPECT_EQ(x.rssi_dbm, y.rssi_dbm);
  }
}

// ---- quantization ------------------------------------------------------------------------------
TEST(Quantization, TwelveBitPhase) {
  const double step = kTwoPi / 4096.0;
  Rng rng(3);
  std::uniform_real_distribution<double> u(-20.0, 20.0);
  for (int i = 0; i < 5000; ++i) {
    const double x = u(rng);
    const double q = quantize_phase(x, 12);
    ASSERT_GE(q, 0.0);
    ASSERT_LT(q, kTwoPi);
    // On the grid, idempotent, and within half a step of the wrapped input (circularly).
    const double k = q / step;
    EXPECT_NEAR(k, std::round(k), 1e-9);
    EXPECT_EQ(quantize_phase(q, 12), q);
    EXPECT_LE(std::abs(wrap_to_pi(q - x)), 0.5 * step + 1e-12);
  }
  // Just below 2π rounds up to the level 4096 ≡ 0.
  EXPECT_EQ(quantize_phase(kTwoPi - 0.1 * step, 12), 0.0);
  EXPECT_DOUBLE_EQ(quantize_phase(0.6 * step, 12), step);
  EXPECT_EQ(quantize_phase(0.4 * step, 12), 0.0);
  // 0 bits: only wrapped
  EXPECT_DOUBLE_EQ(quantize_phase(7.0, 0), 7.0 - kTwoPi);
  // 1 bit: levels 0 and π
  EXPECT_DOUBLE_EQ(quantize_phase(2.0, 1), kPi);
  EXPECT_EQ(quantize_phase(0.5, 1), 0.0);
  // 32 bits works (step 1.46e-9)
  EXPECT_NEAR(quantize_phase(1.0, 32), 1.0, kTwoPi / std::ldexp(1.0, 32));
}

TEST(Quantization, Rssi) {
  EXPECT_EQ(quantize_rssi(-74.43, 1.0), -74.0);
  EXPECT_EQ(quantize_rssi(-74.6, 1.0), -75.0);
  EXPECT_EQ(quantize_rssi(-74.43, 0.5), -74.5);
  EXPECT_EQ(quantize_rssi(-74.2, 0.5), -74.0);
  EXPECT_EQ(quantize_rssi(-74.43, 0.0), -74.43);
  EXPECT_EQ(quantize_rssi(quantize_rssi(-61.37, 0.5), 0.5), quantize_rssi(-61.37, 0.5));
}

// ---- physical model ---------------------------------------------------------------------------
Endpoint at(const Vec3& p, double gain_dbi = 0.0) {
  Endpoint e;
  e.pose.position = p;
  e.pattern = isotropic_pattern(gain_dbi);
  return e;
}

ReaderParams noiseless_physical() {
  ReaderParams r = noiseless_paper();
  r.model = ReaderModelKind::kPhysical;
  r.tx_power_dbm = 30.0;
  r.modulation_factor = 0.25;
  r.sensitivity_dbm = -100.0;
  return r;
}

LinkState ideal_link(double d, double f, double g_r_dbi = 0.0, double g_t_dbi = 0.0, double phi0 = 0.0) {
  IdealChannel ch;
  Endpoint a = at(Vec3(0.3, -0.2, 1.0), g_r_dbi), t = at(Vec3(0.3 + d, -0.2, 1.0), g_t_dbi);
  LinkState l = link_at(d, f, phi0);
  const std::vector<Endpoint> tags{t};
  std::complex<double> h;
  ch.one_way(a, tags, f, std::span<std::complex<double>>(&h, 1));
  l.h_one_way = h;
  return l;
}

// For the ideal channel h = √(G_R G_T)·λ/(4πD)·e^{−jkD}: φ0 − arg(h²) ≡ φ0 + 4πD/λ (mod 2π), i.e. eq. 3.
TEST(PhysicalModel, IdealChannelPhaseEqualsEq3) {
  const ReaderParams r = noiseless_physical();
  TagParams tag;
  Rng rng(1);
  for (double f : {865.7e6, 866.3e6, 866.9e6, 867.5e6})
    for (double d : {0.1, 0.5, 1.234, 2.0, 3.7, 5.5})
      for (double phi0 : {0.0, 1.3}) {
        const Reading rd = physical_reading(r, tag, ideal_link(d, f, 0.0, 0.0, phi0), rng);
        ASSERT_TRUE(rd.read);
        const double eq3 = wrap_to_2pi(phi0 + 4.0 * kPi * d / wavelength_m(f));
        // arg() of a complex number whose angle is ~kD ≤ 100 rad: a few ulps of 100 → 1e-12.
        EXPECT_NEAR(wrap_to_pi(rd.phase_rad - eq3), 0.0, 1e-12) << "f " << f << " d " << d;
      }
}

// Friis, D = 2 m, 865.7 MHz, isotropic: |h|² = (0.0137788644)² = 1.898571e-4 → P_tag = 30 dBm − 37.215731 dB
// = −7.215731 dBm. P_rx = P_tx·K·|h|⁴ = 1 W · 0.25 · 3.604573e-8 → 10·log10(9.011432e-9 W) + 30 = −50.452063 dBm.
// With G_R = 6 dBi, G_T = 2 dBi the one-way gain rises 8 dB and the round trip 16 dB: −34.452063 dBm.
TEST(PhysicalModel, FriisRssi) {
  const ReaderParams r = noiseless_physical();
  TagParams tag;
  Rng rng(1);
  Reading rd = physical_reading(r, tag, ideal_link(2.0, 865.7e6), rng);
  ASSERT_TRUE(rd.read);
  EXPECT_NEAR(rd.rssi_dbm, -50.452063, 1e-6);
  rd = physical_reading(r, tag, ideal_link(2.0, 865.7e6, 6.0, 2.0), rng);
  ASSERT_TRUE(rd.read);
  EXPECT_NEAR(rd.rssi_dbm, -34.452063, 1e-6);
  ReaderParams q = r;
  q.rssi_resolution_db = 0.5;
  EXPECT_DOUBLE_EQ(physical_reading(q, tag, ideal_link(2.0, 865.7e6), rng).rssi_dbm, -50.5);
}

// Tag powered iff P_tx·|h|² ≥ chip sensitivity. 30 dBm, −20 dBm chip, isotropic: |h|² ≥ 1e-5 →
// λ/(4πD) ≥ 3.16228e-3 → D ≤ 0.34630063301 / (4π·3.16228e-3) = 8.714519 m.
TEST(PhysicalModel, PoweredThreshold) {
  const ReaderParams r = noiseless_physical();
  TagParams tag;
  tag.chip_sensitivity_dbm = -20.0;
  Rng rng(1);
  EXPECT_TRUE(physical_reading(r, tag, ideal_link(8.714, 865.7e6), rng).read);
  EXPECT_FALSE(physical_reading(r, tag, ideal_link(8.716, 865.7e6), rng).read);
  // 6 dB less sensitive: D shrinks by 10^(−6/20) = 0.5011872 → 8.714519·0.5011872 = 4.367605 m.
  tag.chip_sensitivity_dbm = -14.0;
  EXPECT_TRUE(physical_reading(r, tag, ideal_link(4.3675, 865.7e6), rng).read);
  EXPECT_FALSE(physical_reading(r, tag, ideal_link(4.3677, 865.7e6), rng).read);
}

// Reader sensitivity: P_rx(2 m) = −50.452063 dBm. Sensitivity −50 dBm → no read at 2 m; P_rx ∝ D⁻⁴, so the
// limit is D = 2·10^(−0.452063/40) = 1.948702 m.
TEST(PhysicalModel, ReaderSensitivityThreshold) {
  ReaderParams r = noiseless_physical();
  r.sensitivity_dbm = -50.0;
  TagParams tag;
  Rng rng(1);
  EXPECT_FALSE(physical_reading(r, tag, ideal_link(2.0, 865.7e6), rng).read);
  EXPECT_TRUE(physical_reading(r, tag, ideal_link(1.9486, 865.7e6), rng).read);
  EXPECT_FALSE(physical_reading(r, tag, ideal_link(1.9488, 865.7e6), rng).read);
  // A zero channel never powers the tag, and never produces a NaN.
  LinkState zero = link_at(2.0);
  zero.h_one_way = 0.0;
  EXPECT_FALSE(physical_reading(r, tag, zero, rng).read);
}

TEST(PhysicalModel, RssiNoiseInDb) {
  ReaderParams r = noiseless_physical();
  r.noise_rssi_db = 0.5;
  TagParams tag;
  Rng rng = make_stream(12, {0});
  const LinkState l = ideal_link(2.0, 865.7e6);
  const int n = 20000;
  double s = 0, s2 = 0;
  for (int i = 0; i < n; ++i) {
    const double e = physical_reading(r, tag, l, rng).rssi_dbm - (-50.452063);
    s += e;
    s2 += e * e;
  }
  const double mean = s / n, sd = std::sqrt(s2 / n - mean * mean);
  EXPECT_NEAR(mean, 0.0, 6 * 0.5 / std::sqrt(n) + 1e-6);
  EXPECT_NEAR(sd, 0.5, 6 * 0.5 / std::sqrt(2.0 * n));
}

TEST(ReaderModel, ReadTagDispatchesOnModel) {
  ReaderParams r = noiseless_physical();
  TagParams tag;
  LinkState l = ideal_link(2.0, 865.7e6);
  l.h_one_way *= std::sqrt(10.0);  // +10 dB one way: physical RSSI +20 dB, paper RSSI unchanged
  Rng rng(1);
  EXPECT_NEAR(read_tag(r, tag, l, rng).rssi_dbm, -30.452063, 1e-6);
  r.model = ReaderModelKind::kPaper;
  EXPECT_NEAR(read_tag(r, tag, l, rng).rssi_dbm, -74.431463, 1e-6);
}

// ---- bad inputs ---------------------------------------------------------------------------------
TEST(ReaderModel, BadLinkInputsThrow) {
  const double nan = std::nan(""), inf = INFINITY;
  ReaderParams paper = noiseless_paper(), phys = noiseless_physical();
  paper.name = "mobile";
  TagParams tag;
  Rng rng(1);
  std::vector<LinkState> bad = {link_at(0.0), link_at(-1.0), link_at(nan), link_at(inf),
                                link_at(2.0, 0.0), link_at(2.0, -865.7e6), link_at(2.0, nan), link_at(2.0, inf),
                                link_at(2.0, 865.7e6, nan)};
  for (const LinkState& l : bad) {
    EXPECT_THROW(paper_reading(paper, l, rng), InputError);
    LinkState lp = l;
    lp.h_one_way = 0.01;
    EXPECT_THROW(physical_reading(phys, tag, lp, rng), InputError);
    EXPECT_THROW(read_tag(paper, tag, l, rng), InputError);
  }
  LinkState h_nan = link_at(2.0);
  h_nan.h_one_way = {nan, 0.0};
  // A non-finite channel is a bug upstream (inputs are range-checked where they enter): an internal error.
  EXPECT_THROW(physical_reading(phys, tag, h_nan, rng), std::logic_error);
  try {
    paper_reading(paper, link_at(0.0), rng);
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mobile"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("distance"), std::string::npos) << e.what();
  }
}

std::string validate_error(const ReaderParams& r) {
  try {
    validate(r, "antennas[1]");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ReaderModel, ValidateReaderNamesEachBadField) {
  EXPECT_EQ(validate_error(ReaderParams{}), "");
  struct Bad {
    const char* field;
    void (*apply)(ReaderParams&);
  };
  const std::vector<Bad> cases = {
      {"frequency", [](ReaderParams& r) { r.frequencies_hz = {}; }},
      {"frequency[0]", [](ReaderParams& r) { r.frequencies_hz = {-865.7e6}; }},
      {"frequency[1]", [](ReaderParams& r) { r.frequencies_hz = {865.7e6, 0.0}; r.phase_offsets_rad = {0, 0}; }},
      {"phase_offset", [](ReaderParams& r) { r.frequencies_hz = {865.7e6, 866.3e6}; }},
      {"phase_offset[0]", [](ReaderParams& r) { r.phase_offsets_rad = {INFINITY}; }},
      {"hop_dwell_s", [](ReaderParams& r) { r.hop_dwell_s = 0.0; }},
      {"tx_power_dbm", [](ReaderParams& r) { r.tx_power_dbm = NAN; }},
      {"noisephi", [](ReaderParams& r) { r.noise_phi_rad = -0.1; }},
      {"noiserssi", [](ReaderParams& r) { r.noise_rssi = -0.01; }},
      {"noise_rssi_db", [](ReaderParams& r) { r.noise_rssi_db = NAN; }},
      {"range", [](ReaderParams& r) { r.range_m = 0.0; }},
      {"range_sigma", [](ReaderParams& r) { r.range_sigma = -0.05; }},
      {"optional_distribution", [](ReaderParams& r) { r.optional_distribution = {DistributionKind::kGamma, {1.0}}; }},
      {"communication_gain", [](ReaderParams& r) { r.communication_gain = 0.0; }},
      {"update_rate", [](ReaderParams& r) { r.update_rate_hz = -15.0; }},
      {"phase_bits", [](ReaderParams& r) { r.phase_bits = 33; }},
      {"phase_bits", [](ReaderParams& r) { r.phase_bits = -1; }},
      {"rssi_resolution_db", [](ReaderParams& r) { r.rssi_resolution_db = -1.0; }},
      {"sensitivity_dbm", [](ReaderParams& r) { r.sensitivity_dbm = INFINITY; }},
      {"modulation_factor", [](ReaderParams& r) { r.modulation_factor = 1.5; }},
      {"pattern", [](ReaderParams& r) { r.pattern.kind = PatternKind::kTable; }},
      {"polarization", [](ReaderParams& r) { r.polarization.axis_local = Vec3::Zero(); }},
  };
  for (const Bad& b : cases) {
    ReaderParams r;
    b.apply(r);
    const std::string msg = validate_error(r);
    EXPECT_NE(msg.find(std::string("antennas[1].") + b.field), std::string::npos)
        << "expected field " << b.field << ", got: '" << msg << "'";
  }
}

TEST(ReaderModel, ValidateTag) {
  EXPECT_NO_THROW(validate(TagParams{}, "tags[0]"));
  TagParams t;
  t.chip_sensitivity_dbm = NAN;
  EXPECT_THROW(validate(t, "tags[0]"), InputError);
  t = TagParams{};
  t.gain_dbi = INFINITY;
  EXPECT_THROW(validate(t, "tags[0]"), InputError);
  t = TagParams{};
  t.pattern.kind = PatternKind::kPatch;
  t.pattern.beamwidth_deg = 200.0;
  try {
    validate(t, "tags[0]");
    FAIL() << "bad pattern accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tags[0].pattern"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rfidray
