#pragma once
// Error statistics of one method over many tags (the paper reports mean / max / min, Fig. 10).
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace rfidray::loc {

struct ErrorSummary {
  int ok = 0, failed = 0;
  double mean_error_m = std::numeric_limits<double>::quiet_NaN();
  double median_error_m = std::numeric_limits<double>::quiet_NaN();
  double max_error_m = std::numeric_limits<double>::quiet_NaN();
  double min_error_m = std::numeric_limits<double>::quiet_NaN();
  double mean_time_ms = std::numeric_limits<double>::quiet_NaN();
};

// errors: of the ok results that have a truth; times: of every attempt.
inline ErrorSummary summarize(std::vector<double> errors, int failed, const std::vector<double>& times_ms) {
  ErrorSummary s;
  s.failed = failed;
  s.ok = static_cast<int>(errors.size());
  if (!times_ms.empty()) {
    double t = 0.0;
    for (double v : times_ms) t += v;
    s.mean_time_ms = t / static_cast<double>(times_ms.size());
  }
  if (errors.empty()) return s;
  std::sort(errors.begin(), errors.end());
  double sum = 0.0;
  for (double e : errors) sum += e;
  const size_t n = errors.size();
  s.mean_error_m = sum / static_cast<double>(n);
  s.median_error_m = n % 2 ? errors[n / 2] : 0.5 * (errors[n / 2 - 1] + errors[n / 2]);
  s.max_error_m = errors.back();
  s.min_error_m = errors.front();
  return s;
}

}  // namespace rfidray::loc
