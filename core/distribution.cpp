#include "core/distribution.h"

#include <cmath>
#include <limits>
#include <random>
#include <sstream>

#include "core/error.h"

namespace rfidray {
namespace {

struct Spec {
  DistributionKind kind;
  const char* name;
  size_t param_count;
  const char* signature;  // shown in error messages
};

// Parameter order follows the std::*_distribution constructors (and the seed plugin).
constexpr Spec kSpecs[] = {
    {DistributionKind::kUniform, "uniform", 2, "[a, b] with a < b"},
    {DistributionKind::kExponential, "exponential", 1, "[lambda] with lambda > 0"},
    {DistributionKind::kGamma, "gamma", 2, "[alpha, beta] with alpha > 0, beta > 0"},
    {DistributionKind::kWeibull, "weibull", 2, "[a, b] with a > 0, b > 0"},
    {DistributionKind::kNormal, "normal", 2, "[mean, stddev] with stddev > 0"},
    {DistributionKind::kLognormal, "lognormal", 2, "[m, s] with s > 0"},
    {DistributionKind::kChiSquared, "chi_squared", 1, "[n] with n > 0"},
    {DistributionKind::kCauchy, "cauchy", 2, "[a, b] with b > 0"},
};

std::string valid_names() {
  std::string s = "none";
  for (const Spec& sp : kSpecs) s += std::string(", ") + sp.name;
  return s;
}

std::string format_params(const std::vector<double>& p) {
  std::ostringstream os;
  os << '[';
  for (size_t i = 0; i < p.size(); ++i) os << (i ? ", " : "") << p[i];
  os << ']';
  return os.str();
}

const Spec* find_spec(DistributionKind kind) {
  for (const Spec& sp : kSpecs)
    if (sp.kind == kind) return &sp;
  return nullptr;
}

}  // namespace

OptionalDistribution parse_distribution(const std::string& name, const std::vector<double>& params,
                                        const std::string& field) {
  if (name.empty() || name == "none") {
    if (!params.empty())
      throw field_error(field, "distribution 'none' takes no parameters (got " + format_params(params) + ")");
    return {};
  }
  // The paper spells "weibul"; accept it and the hyphenated chi-squared as aliases, and the seed plugin's SDF
  // names, which are the <random> class names ("uniform_real_distribution", "normal_distribution", ...).
  std::string canonical = name;
  const std::string suffix = "_distribution";
  if (canonical.size() > suffix.size() && canonical.ends_with(suffix))
    canonical.resize(canonical.size() - suffix.size());
  if (canonical == "uniform_real") canonical = "uniform";
  if (canonical == "weibul") canonical = "weibull";
  if (canonical == "chi-squared") canonical = "chi_squared";
  const Spec* spec = nullptr;
  for (const Spec& sp : kSpecs)
    if (canonical == sp.name) spec = &sp;
  if (!spec) throw field_error(field, "unknown distribution '" + clip(name) + "' (valid: " + valid_names() + ")");

  const std::string pfield = field + "_params";
  auto fail = [&](const std::string& why) {
    return field_error(pfield, std::string(spec->name) + " expects " + spec->signature + "; " + why + " (got " +
                                   format_params(params) + ")");
  };
  if (params.size() != spec->param_count) throw fail("wrong number of parameters");
  for (double v : params)
    if (!std::isfinite(v)) throw fail("parameters must be finite");
  const double p0 = params[0];
  const double p1 = params.size() > 1 ? params[1] : 0.0;
  bool ok = true;
  switch (spec->kind) {
    case DistributionKind::kUniform: ok = p0 < p1; break;
    case DistributionKind::kExponential: ok = p0 > 0.0; break;
    case DistributionKind::kGamma:
    case DistributionKind::kWeibull: ok = p0 > 0.0 && p1 > 0.0; break;
    case DistributionKind::kNormal:
    case DistributionKind::kLognormal:
    case DistributionKind::kCauchy: ok = p1 > 0.0; break;
    case DistributionKind::kChiSquared: ok = p0 > 0.0; break;
    case DistributionKind::kNone: break;
  }
  if (!ok) throw fail("invalid value");
  return OptionalDistribution{spec->kind, params};
}

const char* to_string(DistributionKind kind) {
  if (kind == DistributionKind::kNone) return "none";
  const Spec* sp = find_spec(kind);
  return sp ? sp->name : "?";
}

double sample(const OptionalDistribution& d, Rng& rng) {
  const auto& p = d.params;
  switch (d.kind) {
    case DistributionKind::kNone: return 0.0;
    case DistributionKind::kUniform: return std::uniform_real_distribution<double>(p[0], p[1])(rng);
    case DistributionKind::kExponential: return std::exponential_distribution<double>(p[0])(rng);
    case DistributionKind::kGamma: return std::gamma_distribution<double>(p[0], p[1])(rng);
    case DistributionKind::kWeibull: return std::weibull_distribution<double>(p[0], p[1])(rng);
    case DistributionKind::kNormal: return std::normal_distribution<double>(p[0], p[1])(rng);
    case DistributionKind::kLognormal: return std::lognormal_distribution<double>(p[0], p[1])(rng);
    case DistributionKind::kChiSquared: return std::chi_squared_distribution<double>(p[0])(rng);
    case DistributionKind::kCauchy: return std::cauchy_distribution<double>(p[0], p[1])(rng);
  }
  return 0.0;
}

double distribution_mean(const OptionalDistribution& d) {
  const auto& p = d.params;
  switch (d.kind) {
    case DistributionKind::kNone: return 0.0;
    case DistributionKind::kUniform: return 0.5 * (p[0] + p[1]);
    case DistributionKind::kExponential: return 1.0 / p[0];
    case DistributionKind::kGamma: return p[0] * p[1];                                  // α β (β = scale)
    case DistributionKind::kWeibull: return p[1] * std::tgamma(1.0 + 1.0 / p[0]);       // b Γ(1 + 1/a)
    case DistributionKind::kNormal: return p[0];
    case DistributionKind::kLognormal: return std::exp(p[0] + 0.5 * p[1] * p[1]);
    case DistributionKind::kChiSquared: return p[0];
    case DistributionKind::kCauchy: return std::numeric_limits<double>::quiet_NaN();  // undefined
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double distribution_variance(const OptionalDistribution& d) {
  const auto& p = d.params;
  switch (d.kind) {
    case DistributionKind::kNone: return 0.0;
    case DistributionKind::kUniform: return (p[1] - p[0]) * (p[1] - p[0]) / 12.0;
    case DistributionKind::kExponential: return 1.0 / (p[0] * p[0]);
    case DistributionKind::kGamma: return p[0] * p[1] * p[1];
    case DistributionKind::kWeibull: {
      const double g1 = std::tgamma(1.0 + 1.0 / p[0]);
      const double g2 = std::tgamma(1.0 + 2.0 / p[0]);
      return p[1] * p[1] * (g2 - g1 * g1);
    }
    case DistributionKind::kNormal: return p[1] * p[1];
    case DistributionKind::kLognormal: {
      const double s2 = p[1] * p[1];
      return std::expm1(s2) * std::exp(2.0 * p[0] + s2);
    }
    case DistributionKind::kChiSquared: return 2.0 * p[0];
    case DistributionKind::kCauchy: return std::numeric_limits<double>::quiet_NaN();
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace rfidray
