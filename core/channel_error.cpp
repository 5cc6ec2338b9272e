#include "core/channel_error.h"

#include "core/number_text.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <vector>

#include "core/units.h"

namespace rfidray {
namespace {

// Nearest-rank percentile of a sorted sample (0 when empty).
double percentile(const std::vector<double>& sorted, double p) {
  if (sorted.empty()) return 0.0;
  const size_t rank = static_cast<size_t>(std::ceil(p / 100.0 * sorted.size()));
  return sorted[std::clamp<size_t>(rank, 1, sorted.size()) - 1];
}

double wrap_abs(double x) { return std::abs(std::remainder(x, kTwoPi)); }

}  // namespace

ChannelErrorStats channel_errors(std::span<const std::complex<double>> reference,
                                 std::span<const std::complex<double>> test,
                                 std::span<const double> min_readable_h2) {
  if (reference.size() != test.size() || reference.size() != min_readable_h2.size())
    throw std::invalid_argument("channel_errors: spans of different lengths");
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> phase, rssi, magnitude, phase_both, rssi_both;
  ChannelErrorStats s;
  for (size_t i = 0; i < reference.size(); ++i) {
    const double r2 = std::norm(reference[i]), t2 = std::norm(test[i]);
    const bool r_ok = r2 >= min_readable_h2[i], t_ok = t2 >= min_readable_h2[i];
    if (!r_ok && !t_ok) continue;
    ++s.links;
    if (r_ok != t_ok) {
      ++s.status_mismatches;
      phase.push_back(kInf);
      rssi.push_back(kInf);
      magnitude.push_back(kInf);
      continue;
    }
    phase.push_back(wrap_abs(std::arg(test[i] * test[i]) - std::arg(reference[i] * reference[i])));
    rssi.push_back(std::abs(10.0 * std::log10(t2 / r2)) * 2.0);  // 40·log10|h| = 20·log10|h|²
    magnitude.push_back(std::abs(std::sqrt(t2 / r2) - 1.0));
    phase_both.push_back(phase.back());
    rssi_both.push_back(rssi.back());
  }
  for (auto* v : {&phase, &rssi, &magnitude, &phase_both, &rssi_both}) std::sort(v->begin(), v->end());
  s.phase_p95_both_rad = percentile(phase_both, 95), s.rssi_p95_both_db = percentile(rssi_both, 95);
  s.phase_p50_rad = percentile(phase, 50), s.phase_p95_rad = percentile(phase, 95);
  s.phase_max_rad = phase.empty() ? 0.0 : phase.back();
  s.rssi_p50_db = percentile(rssi, 50), s.rssi_p95_db = percentile(rssi, 95);
  s.rssi_max_db = rssi.empty() ? 0.0 : rssi.back();
  s.magnitude_p50 = percentile(magnitude, 50), s.magnitude_p95 = percentile(magnitude, 95);
  return s;
}

std::string error_text(double value, int significant_digits, const std::string& not_finite) {
  return std::isfinite(value) ? rounded_text(value, significant_digits) : not_finite;
}

}  // namespace rfidray
