// The closed-form read probability (core/read_probability.h) against the reader model itself: the share of
// read_tag() attempts that read, over many independent draws, must match it within the binomial error.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/random.h"
#include "core/read_probability.h"
#include "core/reader_model.h"
#include "core/units.h"

namespace rfidray {
namespace {

LinkState link_at(double d, double f = 865.7e6) {
  LinkState l;
  l.distance_m = d;
  l.frequency_hz = f;
  return l;
}

// Share of N attempts read; N = 40 000 gives a binomial σ ≤ 0.0025, so 4σ = 0.01.
double monte_carlo(const ReaderParams& r, const TagParams& t, const LinkState& l) {
  Rng rng = make_stream(7, {static_cast<uint64_t>(l.distance_m * 1000)});
  int reads = 0;
  const int n = 40000;
  for (int i = 0; i < n; ++i) reads += read_tag(r, t, l, rng).read;
  return static_cast<double>(reads) / n;
}

TEST(ReadProbability, PaperModelMatchesItsDraws) {
  ReaderParams r;  // paper model: range 7 m, σ_r = 0.05, n_RSSI σ = 0.01, G_RT = 1
  const TagParams t;
  for (double d : {1.0, 6.5, 6.9, 7.0, 7.2, 7.5, 9.0}) {
    const double p = read_probability(r, t, link_at(d));
    EXPECT_NEAR(p, monte_carlo(r, t, link_at(d)), 0.01) << "D = " << d;
  }
  // At D = r the range test passes half the time: P(|1 + n_r| ≥ 1) = P(n_r ≥ 0) + P(n_r ≤ −2) ≈ 0.5.
  r.noise_rssi = 0.0;
  EXPECT_NEAR(read_probability(r, t, link_at(7.0)), 0.5, 1e-12);
  // The RSSI noise decides far out: amplitude A = G·λ/(4πD) against σ: P = Φ(A/σ).
  r.range_m = 1000.0;
  r.noise_rssi = 0.003;
  const double a = wavelength_m(865.7e6) / (4.0 * kPi * 10.0);
  EXPECT_NEAR(read_probability(r, t, link_at(10.0)), standard_normal_cdf(a / 0.003), 1e-9);
  EXPECT_NEAR(read_probability(r, t, link_at(10.0)), monte_carlo(r, t, link_at(10.0)), 0.01);
  // A reader's report probability multiplies.
  r.read_probability = {0.3};
  EXPECT_NEAR(read_probability(r, t, link_at(10.0)), 0.3 * standard_normal_cdf(a / 0.003), 1e-9);
  EXPECT_NEAR(read_probability(r, t, link_at(10.0)), monte_carlo(r, t, link_at(10.0)), 0.01);
}

TEST(ReadProbability, PhysicalModelIsTheThreshold) {
  ReaderParams r;
  r.model = ReaderModelKind::kPhysical;
  const TagParams t;  // chip −20 dBm; reader 30 dBm → readable iff |h|² ≥ −50 dB (reader side: −52 dB)
  const double h2_min = min_readable_h2(r, t);
  EXPECT_NEAR(linear_to_db(h2_min), -50.0, 1e-9);
  for (double db : {-49.9, -50.1, -30.0, -70.0}) {
    LinkState l = link_at(3.0);
    l.h_one_way = std::polar(std::sqrt(db_to_linear(db)), 0.3);
    const double p = read_probability(r, t, l);
    EXPECT_EQ(p, db >= -50.0 ? 1.0 : 0.0) << db;
    EXPECT_EQ(p, monte_carlo(r, t, l)) << db;
  }
  r.read_probability = {0.2, 0.8};
  r.frequencies_hz = {865.7e6, 866.3e6};
  r.phase_offsets_rad = {0.0, 0.0};
  LinkState l = link_at(3.0);
  l.h_one_way = 0.01;  // −40 dB
  l.hop_index = 1;
  EXPECT_EQ(read_probability(r, t, l), 0.8);
  EXPECT_NEAR(monte_carlo(r, t, l), 0.8, 0.01);
}

TEST(ReadProbability, RejectsWhatTheModelRejects) {
  const ReaderParams r;
  EXPECT_THROW(read_probability(r, TagParams{}, link_at(0.0)), InputError);
  EXPECT_THROW(read_probability(r, TagParams{}, link_at(std::nan(""))), InputError);
  EXPECT_THROW(read_probability(r, TagParams{}, link_at(1.0, -1.0)), InputError);
}

}  // namespace
}  // namespace rfidray
