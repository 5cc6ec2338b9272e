// Hardware effects of real readers (core/reader.h): phase-centre offset, antenna and tag phase patterns,
// receiver noise that grows near sensitivity, read probability per carrier. Each against its closed form.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/reader_model.h"
#include "core/simulation.h"
#include "core/random.h"
#include "core/units.h"

namespace rfidray {
namespace {

constexpr double kF = 865.7e6;

// One fixed antenna and one tag, noise-free, unquantized.
Scenario one_link(ReaderModelKind model, const Vec3& tag, const Quat& antenna_orientation = Quat::Identity()) {
  Scenario s;
  AntennaSpec a;
  a.reader.name = "A";
  a.reader.model = model;
  a.reader.noise_phi_rad = 0.0;
  a.reader.noise_rssi = 0.0;
  a.reader.noise_rssi_db = 0.0;
  a.reader.range_sigma = 0.0;
  a.reader.phase_bits = 0;
  a.reader.rssi_resolution_db = 0.0;
  a.motion.pose.orientation = antenna_orientation;
  s.antennas.push_back(a);
  TagSpec t;
  t.tag.name = "t";
  t.motion.pose.position = tag;
  s.tags.push_back(t);
  s.duration_s = 0.0;  // one tick
  return s;
}

double only_phase(const Scenario& s) {
  const SimulationResult r = simulate(s, IdealChannel{});
  EXPECT_EQ(r.antennas[0].reads.size(), 1u);
  return r.antennas[0].reads.at(0).reading.phase_rad;
}

double phase_of_distance(double d) { return wrap_to_2pi(4.0 * kPi * d / wavelength_m(kF)); }

TEST(HardwareEffects, PhaseCentreOffsetMovesThePhysicsNotTheReportedPose) {
  for (ReaderModelKind model : {ReaderModelKind::kPaper, ReaderModelKind::kPhysical}) {
    Scenario s = one_link(model, Vec3(2, 0, 0));
    s.antennas[0].reader.phase_centre_offset_m = Vec3(0.1, 0, 0);  // 10 cm ahead along boresight
    const SimulationResult r = simulate(s, IdealChannel{});
    ASSERT_EQ(r.antennas[0].reads.size(), 1u);
    const ReadRecord& rec = r.antennas[0].reads[0];
    EXPECT_NEAR(rec.distance_m, 1.9, 1e-12);
    EXPECT_NEAR(std::remainder(rec.reading.phase_rad - phase_of_distance(1.9), kTwoPi), 0.0, 1e-9);
    EXPECT_EQ(rec.antenna_pose.position, Vec3::Zero());  // the reads report the mounting pose
  }
  // The offset is in the antenna frame: yawed 90°, +X of the antenna is world +Y.
  Scenario s = one_link(ReaderModelKind::kPaper, Vec3(0, 2, 0), Quat(Eigen::AngleAxisd(kPi / 2, Vec3::UnitZ())));
  s.antennas[0].reader.phase_centre_offset_m = Vec3(0.1, 0, 0);
  EXPECT_NEAR(std::remainder(only_phase(s) - phase_of_distance(1.9), kTwoPi), 0.0, 1e-9);
}

TEST(HardwareEffects, PhasePatternsAddTheirPolynomialAlongTheDirection) {
  // Tag at azimuth 30° seen from the antenna; the antenna at azimuth 180° + 30° seen from the (unrotated) tag.
  const double az = kPi / 6;
  const Vec3 tag(2 * std::cos(az), 2 * std::sin(az), 0);
  Scenario s = one_link(ReaderModelKind::kPhysical, tag);
  s.antennas[0].reader.phase_pattern.azimuth_rad = {0.5, 0.2};  // 0.5·az + 0.2·az²
  const double expected_antenna = 0.5 * az + 0.2 * az * az;
  EXPECT_NEAR(std::remainder(only_phase(s) - phase_of_distance(2.0) - expected_antenna, kTwoPi), 0.0, 1e-9);
  s.tags[0].tag.phase_pattern.azimuth_rad = {0.3};  // tag sees the antenna at az − π (atan2 → −150°)
  const double expected_tag = 0.3 * (az - kPi);
  EXPECT_NEAR(std::remainder(only_phase(s) - phase_of_distance(2.0) - expected_antenna - expected_tag, kTwoPi), 0.0,
              1e-9);
  // Elevation: a tag 45° above boresight.
  Scenario e = one_link(ReaderModelKind::kPaper, Vec3(1, 0, 1));
  e.antennas[0].reader.phase_pattern.elevation_rad = {0.0, -0.4};
  EXPECT_NEAR(std::remainder(only_phase(e) - phase_of_distance(std::sqrt(2.0)) + 0.4 * kPi * kPi / 16, kTwoPi), 0.0,
              1e-9);
}

TEST(HardwareEffects, TagPhaseRippleIsItsHarmonicSumAndHasTheDrawnRms) {
  // The ripple enters the phase like the polynomial: along the direction of the antenna in the tag frame.
  const double az = kPi / 6;
  const Vec3 tag(2 * std::cos(az), 2 * std::sin(az), 0);
  Scenario s = one_link(ReaderModelKind::kPhysical, tag);
  PhasePattern& p = s.tags[0].tag.phase_pattern;
  p.ripple_cos_rad = {0.0, 0.3};
  p.ripple_sin_rad = {0.0, -0.2};
  const double seen = az - kPi;  // the antenna from the unrotated tag
  const double expected = 0.3 * std::cos(4 * seen) - 0.2 * std::sin(4 * seen);
  EXPECT_NEAR(std::remainder(only_phase(s) - phase_of_distance(2.0) - expected, kTwoPi), 0.0, 1e-9);

  // Drawn: harmonics ⌈N/2⌉…N only (N = round(π / scale)), RMS over azimuth about the median σ. For one element
  // the mean square over azimuth is Σ (c² + s²)/2 exactly; over many elements its mean is σ² e^{2·spread²}
  // (log-normal) — 2000 draws: a χ² of 8000 degrees of freedom, relative sd of the mean ≈ 1.6 %·(1 + spread).
  for (double spread : {0.0, 0.6}) {
    Rng rng = make_stream(7, {1});
    double mean_square = 0.0;
    const int draws = 2000;
    for (int k = 0; k < draws; ++k) {
      PhasePattern d;
      draw_phase_ripple(d, 0.35, kPi / 6, spread, rng);  // 30°: N = 6, harmonics 3…6
      ASSERT_EQ(d.ripple_cos_rad.size(), 6u);
      for (int n = 0; n < 2; ++n) {
        ASSERT_EQ(d.ripple_cos_rad[n], 0.0);
        ASSERT_EQ(d.ripple_sin_rad[n], 0.0);
      }
      double ms = 0.0, numeric = 0.0;
      for (size_t n = 0; n < 6; ++n) ms += 0.5 * (d.ripple_cos_rad[n] * d.ripple_cos_rad[n] + d.ripple_sin_rad[n] * d.ripple_sin_rad[n]);
      // The same mean square by integrating the ripple over one period of azimuth (π).
      for (int i = 0; i < 720; ++i) {
        const double a = -kPi / 2 + kPi * i / 720;
        const double v = d.phase_rad(Vec3(std::cos(a), std::sin(a), 0.0));
        numeric += v * v / 720;
      }
      ASSERT_NEAR(numeric, ms, 1e-12 + 1e-9 * ms);
      mean_square += ms / draws;
    }
    const double expected_ms = 0.35 * 0.35 * std::exp(2 * spread * spread);
    EXPECT_NEAR(mean_square, expected_ms, 0.06 * (1 + 2 * spread) * expected_ms) << spread;
  }
  // Deterministic: the same stream draws the same ripple.
  PhasePattern a, b;
  Rng r1 = make_stream(3, {9}), r2 = make_stream(3, {9});
  draw_phase_ripple(a, 0.2, kPi / 10, 0.5, r1);
  draw_phase_ripple(b, 0.2, kPi / 10, 0.5, r2);
  EXPECT_EQ(a.ripple_cos_rad, b.ripple_cos_rad);
  EXPECT_EQ(a.ripple_sin_rad, b.ripple_sin_rad);
}

// Sample standard deviation of the phase about its circular mean, over many ticks of one link.
double phase_std(Scenario s, int ticks) {
  s.antennas[0].reader.update_rate_hz = 100.0;
  s.duration_s = (ticks - 1) / 100.0;
  const SimulationResult r = simulate(s, IdealChannel{});
  std::complex<double> m{0, 0};
  for (const ReadRecord& rec : r.antennas[0].reads) m += std::polar(1.0, rec.reading.phase_rad);
  double sum2 = 0.0;
  for (const ReadRecord& rec : r.antennas[0].reads) {
    const double d = std::remainder(rec.reading.phase_rad - std::arg(m), kTwoPi);
    sum2 += d * d;
  }
  return std::sqrt(sum2 / (r.antennas[0].reads.size() - 1));
}

TEST(HardwareEffects, ReceiverNoiseGrowsAsTheSignalNearsSensitivity) {
  // Physical model, isotropic antennas: P_rx = P_tx·K·|h|⁴ with |h| = λ/(4πD).
  const double snr_s_db = 6.0, sigma0 = 0.05;
  for (double d : {1.0, 4.0}) {
    Scenario s = one_link(ReaderModelKind::kPhysical, Vec3(d, 0, 0));
    ReaderParams& r = s.antennas[0].reader;
    r.noise_phi_rad = sigma0;
    r.snr_at_sensitivity_db = snr_s_db;
    const double h = wavelength_m(kF) / (4 * kPi * d);
    const double p_rx = dbm_to_watt(r.tx_power_dbm) * r.modulation_factor * std::pow(h, 4);
    const double snr = std::pow(10.0, snr_s_db / 10) * p_rx / dbm_to_watt(r.sensitivity_dbm);
    const double expected = std::sqrt(sigma0 * sigma0 + 0.5 / snr);
    // 4000 normal draws: the sample σ has a relative standard error 1/√(2·4000) ≈ 1.1 %; 5 % is 4.5 of them.
    EXPECT_NEAR(phase_std(s, 4000), expected, 0.05 * expected) << "D = " << d;
  }
  // Off by default: the same link without the term keeps σ0.
  Scenario s = one_link(ReaderModelKind::kPhysical, Vec3(4, 0, 0));
  s.antennas[0].reader.noise_phi_rad = sigma0;
  EXPECT_NEAR(phase_std(s, 4000), sigma0, 0.05 * sigma0);
}

TEST(HardwareEffects, ReadProbabilityPerCarrier) {
  Scenario s = one_link(ReaderModelKind::kPaper, Vec3(2, 0, 0));
  ReaderParams& r = s.antennas[0].reader;
  r.frequencies_hz = {865.7e6, 866.3e6};
  r.phase_offsets_rad = {0.0, 0.0};
  r.hop_dwell_s = 0.5;
  r.read_probability = {0.25, 0.75};
  r.update_rate_hz = 100.0;
  s.duration_s = 99.99;  // 10 000 ticks, 5 000 per carrier
  const SimulationResult res = simulate(s, IdealChannel{});
  size_t reads[2] = {0, 0};
  for (const ReadRecord& rec : res.antennas[0].reads) ++reads[rec.hop_index];
  // Binomial(5000, p): σ = √(5000·p(1−p)) ≈ 31; ±150 is about 5 σ.
  EXPECT_NEAR(static_cast<double>(reads[0]), 1250.0, 150.0);
  EXPECT_NEAR(static_cast<double>(reads[1]), 3750.0, 150.0);
  // Deterministic: the same seed gives the same reads at another thread count.
  SimulationOptions one;
  one.threads = 1;
  EXPECT_EQ(simulate(s, IdealChannel{}, one).antennas[0].reads.size(), res.antennas[0].reads.size());
}

TEST(HardwareEffects, BadValuesNameTheField) {
  Scenario s = one_link(ReaderModelKind::kPaper, Vec3(2, 0, 0));
  s.antennas[0].reader.read_probability = {1.5};
  try {
    simulate(s, IdealChannel{});
    FAIL() << "read_probability 1.5 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("read_probability"), std::string::npos) << e.what();
  }
  s.antennas[0].reader.read_probability.clear();
  s.antennas[0].reader.phase_centre_offset_m = Vec3(std::nan(""), 0, 0);
  EXPECT_THROW(simulate(s, IdealChannel{}), InputError);
}

}  // namespace
}  // namespace rfidray
