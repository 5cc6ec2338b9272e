// The paper's optional noise n_optional (eq. 4): the eight <random> distributions, their parsing and
// their closed-form moments.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/distribution.h"
#include "core/error.h"
#include "tests/support/input_error.h"

namespace rfidray {
namespace {

constexpr int kSamples = 200000;

struct Moments {
  double mean = 0.0;
  double variance = 0.0;  // unbiased
  double m4 = 0.0;        // fourth central moment (for the standard error of the variance)
};

Moments sample_moments(const OptionalDistribution& d, uint64_t seed) {
  Rng rng = make_stream(seed, {1});
  std::vector<double> x(kSamples);
  for (double& v : x) v = sample(d, rng);
  Moments m;
  for (double v : x) m.mean += v;
  m.mean /= kSamples;
  for (double v : x) {
    const double c = (v - m.mean) * (v - m.mean);
    m.variance += c;
    m.m4 += c * c;
  }
  m.variance /= (kSamples - 1);
  m.m4 /= kSamples;
  return m;
}

struct Case {
  std::string name;
  std::vector<double> params;
};

class DistributionMoments : public ::testing::TestWithParam<Case> {};

// Sample mean within 6 standard errors σ/√N of the closed-form mean; sample variance within 6 standard
// errors √((μ4 − σ⁴)/N) of the closed-form variance (μ4 estimated from the sample). A 6σ band fails by
// chance with probability ~2e-9 per check, so a failure means the formula or the sampler is wrong.
TEST_P(DistributionMoments, MeanAndVarianceMatchClosedForm) {
  const Case& c = GetParam();
  const OptionalDistribution d = parse_distribution(c.name, c.params, "optional_distribution");
  const double mean = distribution_mean(d);
  const double var = distribution_variance(d);
  ASSERT_TRUE(std::isfinite(mean));
  ASSERT_GT(var, 0.0);
  const Moments m = sample_moments(d, 42);
  const double se_mean = std::sqrt(var / kSamples);
  EXPECT_NEAR(m.mean, mean, 6.0 * se_mean) << c.name;
  const double se_var = std::sqrt(std::max(m.m4 - var * var, 0.0) / kSamples);
  EXPECT_NEAR(m.variance, var, 6.0 * se_var) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    Eight, DistributionMoments,
    ::testing::Values(Case{"uniform", {-0.5, 1.5}}, Case{"exponential", {2.0}}, Case{"gamma", {2.5, 0.3}},
                      Case{"weibull", {1.7, 0.8}}, Case{"normal", {0.2, 0.4}}, Case{"lognormal", {-1.0, 0.5}},
                      Case{"chi_squared", {3.0}}),
    [](const ::testing::TestParamInfo<Case>& i) { return i.param.name; });

TEST(Distribution, ClosedFormsAgainstHandValues) {
  auto d = [](const char* n, std::vector<double> p) { return parse_distribution(n, p, "f"); };
  // uniform [-0.5, 1.5]: mean 0.5, variance 2²/12 = 1/3
  EXPECT_DOUBLE_EQ(distribution_mean(d("uniform", {-0.5, 1.5})), 0.5);
  EXPECT_DOUBLE_EQ(distribution_variance(d("uniform", {-0.5, 1.5})), 1.0 / 3.0);
  // exponential λ = 2: mean 1/2, variance 1/4
  EXPECT_DOUBLE_EQ(distribution_mean(d("exponential", {2.0})), 0.5);
  EXPECT_DOUBLE_EQ(distribution_variance(d("exponential", {2.0})), 0.25);
  // gamma α = 2.5, β = 0.3 (scale): mean 0.75, variance 2.5·0.09 = 0.225
  EXPECT_DOUBLE_EQ(distribution_mean(d("gamma", {2.5, 0.3})), 0.75);
  EXPECT_NEAR(distribution_variance(d("gamma", {2.5, 0.3})), 0.225, 1e-15);
  // weibull a = 1 is exponential with scale b: mean b, variance b²
  EXPECT_NEAR(distribution_mean(d("weibull", {1.0, 0.8})), 0.8, 1e-15);
  EXPECT_NEAR(distribution_variance(d("weibull", {1.0, 0.8})), 0.64, 1e-15);
  // weibull a = 2, b = 1: mean Γ(1.5) = √π/2, variance 1 − π/4
  EXPECT_NEAR(distribution_mean(d("weibull", {2.0, 1.0})), std::sqrt(M_PI) / 2.0, 1e-15);
  EXPECT_NEAR(distribution_variance(d("weibull", {2.0, 1.0})), 1.0 - M_PI / 4.0, 1e-15);
  // lognormal m = 0, s = 1: mean e^{1/2}, variance (e − 1)·e
  EXPECT_NEAR(distribution_mean(d("lognormal", {0.0, 1.0})), std::exp(0.5), 1e-15);
  EXPECT_NEAR(distribution_variance(d("lognormal", {0.0, 1.0})), (M_E - 1.0) * M_E, 1e-14);
  // chi-squared n = 3: mean 3, variance 6
  EXPECT_DOUBLE_EQ(distribution_mean(d("chi_squared", {3.0})), 3.0);
  EXPECT_DOUBLE_EQ(distribution_variance(d("chi_squared", {3.0})), 6.0);
  // Cauchy has neither
  EXPECT_TRUE(std::isnan(distribution_mean(d("cauchy", {0.0, 1.0}))));
  EXPECT_TRUE(std::isnan(distribution_variance(d("cauchy", {0.0, 1.0}))));
}

// Cauchy(a, b) has no mean: check the median a and the interquartile range 2b instead. The sample
// p-quantile has standard error √(p(1−p)/N)/f(x_p); at the quartiles and the median of Cauchy(0, b)
// f = 1/(2πb) and 1/(πb): se(median) = πb/(2√N), se(quartile) = 2πb·√(3/16)/√N. 6σ bands.
TEST(Distribution, CauchyMedianAndIqr) {
  const double a = 0.3, b = 0.2;
  const OptionalDistribution d = parse_distribution("cauchy", {a, b}, "f");
  Rng rng = make_stream(7, {2});
  std::vector<double> x(kSamples);
  for (double& v : x) v = sample(d, rng);
  std::sort(x.begin(), x.end());
  const double median = x[kSamples / 2];
  const double q1 = x[kSamples / 4], q3 = x[3 * kSamples / 4];
  const double se_median = M_PI * b / (2.0 * std::sqrt(double(kSamples)));
  const double se_q = 2.0 * M_PI * b * std::sqrt(3.0 / 16.0) / std::sqrt(double(kSamples));
  EXPECT_NEAR(median, a, 6.0 * se_median);
  // IQR = q3 − q1; its se ≤ se(q1) + se(q3).
  EXPECT_NEAR(q3 - q1, 2.0 * b, 6.0 * 2.0 * se_q);
}

TEST(Distribution, NoneSamplesZeroAndIsDefault) {
  const OptionalDistribution d = parse_distribution("none", {}, "f");
  EXPECT_EQ(d.kind, DistributionKind::kNone);
  EXPECT_EQ(parse_distribution("", {}, "f").kind, DistributionKind::kNone);
  Rng rng(1);
  EXPECT_EQ(sample(d, rng), 0.0);
  EXPECT_EQ(distribution_mean(d), 0.0);
}

TEST(Distribution, SameSeedSameSamples) {
  const OptionalDistribution d = parse_distribution("gamma", {2.0, 1.0}, "f");
  Rng a = make_stream(5, {3}), b = make_stream(5, {3});
  for (int i = 0; i < 100; ++i) EXPECT_EQ(sample(d, a), sample(d, b));
}

TEST(Distribution, NamesRoundTrip) {
  for (const char* n : {"uniform", "exponential", "gamma", "weibull", "normal", "lognormal", "chi_squared", "cauchy"}) {
    const size_t count = std::string(n) == "exponential" || std::string(n) == "chi_squared" ? 1 : 2;
    const OptionalDistribution d = parse_distribution(n, count == 1 ? std::vector<double>{1.0} : std::vector<double>{0.5, 1.0}, "f");
    EXPECT_STREQ(to_string(d.kind), n);
  }
  EXPECT_EQ(parse_distribution("weibul", {1.0, 1.0}, "f").kind, DistributionKind::kWeibull);  // paper spelling
}

std::string error_of(const std::string& name, const std::vector<double>& p) {
  return testing::input_error_of([&] { parse_distribution(name, p, "antennas[0].optional_distribution"); });
}

TEST(Distribution, UnknownNameListsValidNamesAndField) {
  const std::string msg = error_of("poisson", {1.0});
  ASSERT_FALSE(msg.empty());
  EXPECT_NE(msg.find("antennas[0].optional_distribution"), std::string::npos) << msg;
  EXPECT_NE(msg.find("poisson"), std::string::npos) << msg;
  for (const char* n : {"uniform", "exponential", "gamma", "weibull", "normal", "lognormal", "chi_squared", "cauchy"})
    EXPECT_NE(msg.find(n), std::string::npos) << msg;
}

TEST(Distribution, EveryInvalidParameterRejected) {
  const double nan = std::nan(""), inf = INFINITY;
  const std::vector<Case> bad = {
      {"uniform", {1.0, 1.0}},   {"uniform", {2.0, 1.0}},   {"uniform", {1.0}},        {"uniform", {0.0, inf}},
      {"exponential", {0.0}},    {"exponential", {-1.0}},   {"exponential", {1, 2}},   {"exponential", {nan}},
      {"gamma", {0.0, 1.0}},     {"gamma", {1.0, 0.0}},     {"gamma", {-1.0, 1.0}},    {"gamma", {1.0}},
      {"weibull", {0.0, 1.0}},   {"weibull", {1.0, -2.0}},  {"weibull", {1.0, 1.0, 1.0}},
      {"normal", {0.0, 0.0}},    {"normal", {0.0, -1.0}},   {"normal", {nan, 1.0}},    {"normal", {}},
      {"lognormal", {0.0, 0.0}}, {"lognormal", {0.0, -1.0}}, {"lognormal", {0.0}},
      {"chi_squared", {0.0}},    {"chi_squared", {-3.0}},   {"chi_squared", {}},
      {"cauchy", {0.0, 0.0}},    {"cauchy", {0.0, -1.0}},   {"cauchy", {inf, 1.0}},    {"cauchy", {1.0}},
      {"none", {1.0}},
  };
  for (const Case& c : bad) {
    const std::string msg = error_of(c.name, c.params);
    EXPECT_FALSE(msg.empty()) << c.name << " with " << c.params.size() << " params was accepted";
    EXPECT_NE(msg.find("antennas[0].optional_distribution"), std::string::npos) << msg;
  }
  // The message for a bad parameter names the params field.
  EXPECT_NE(error_of("gamma", {0.0, 1.0}).find("optional_distribution_params"), std::string::npos);
}

}  // namespace
}  // namespace rfidray
