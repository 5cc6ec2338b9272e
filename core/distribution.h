#pragma once
// The paper's optional noise n_optional (eq. 4): one of eight <random> distributions with validated
// parameters. Names and parameter order follow the seed plugin / std::*_distribution constructors.
#include <string>
#include <vector>

#include "core/random.h"
#include "core/reader.h"

namespace rfidray {

// "uniform" [a, b) a<b | "exponential" [λ>0] | "gamma" [α>0, β>0] | "weibull" [a>0, b>0] |
// "normal" [μ, σ>0] | "lognormal" [m, s>0] | "chi_squared" [n>0] | "cauchy" [a, b>0]; "none"/"" → kNone.
// Aliases: "weibul" (the paper's spelling) → weibull, "chi-squared" → chi_squared, and the seed plugin's SDF
// names "<name>_distribution" ("uniform_real_distribution" → uniform). Parameters must be finite.
// Throws InputError naming `field` for an unknown name (listing the valid names), and `field` + "_params"
// (e.g. optional_distribution_params, the seed plugin's name) for a wrong parameter count or value.
OptionalDistribution parse_distribution(const std::string& name, const std::vector<double>& params,
                                        const std::string& field);
const char* to_string(DistributionKind kind);
// Draws one sample (0 for kNone). Deterministic for a given generator state.
double sample(const OptionalDistribution& d, Rng& rng);
// Closed-form mean and variance (NaN where undefined, e.g. Cauchy), for tests and docs.
double distribution_mean(const OptionalDistribution& d);
double distribution_variance(const OptionalDistribution& d);

}  // namespace rfidray
