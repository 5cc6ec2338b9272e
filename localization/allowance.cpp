#include "localization/allowance.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "localization/methods.h"
#include "localization/summary.h"

namespace rfidray::loc {

Allowance choose_allowance(const std::vector<AllowanceSample>& samples, double coverage) {
  Allowance best;
  best.samples = static_cast<int>(samples.size());
  if (samples.empty()) return best;
  const size_t n = samples.size();
  const size_t need = static_cast<size_t>(std::ceil(coverage * static_cast<double>(n)));
  best.median_radius_m = std::numeric_limits<double>::infinity();
  for (double factor : {0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 8.0}) {
    // The base each sample needs to be covered (0 when the factor alone covers it).
    std::vector<double> need_base(n);
    for (size_t i = 0; i < n; ++i) {
      const AllowanceSample& s = samples[i];
      const double reach = s.statistical_radius_m + factor * s.smooth_residual_rad * s.bias_m_per_rad;
      need_base[i] = reach >= s.error_m ? 0.0
                     : s.bias_m_per_rad > 0.0 ? (s.error_m - s.statistical_radius_m) / s.bias_m_per_rad
                                              : std::numeric_limits<double>::infinity();
    }
    std::vector<double> sorted = need_base;
    std::sort(sorted.begin(), sorted.end());
    const double base = sorted[std::min(n, std::max<size_t>(need, 1)) - 1];
    if (!std::isfinite(base)) continue;
    std::vector<double> radius(n);
    size_t covered = 0;
    for (size_t i = 0; i < n; ++i) {
      const AllowanceSample& s = samples[i];
      radius[i] = s.statistical_radius_m + std::max(base, factor * s.smooth_residual_rad) * s.bias_m_per_rad;
      covered += radius[i] >= s.error_m;
    }
    std::nth_element(radius.begin(), radius.begin() + n / 2, radius.end());
    const double median = radius[n / 2];
    if (median < best.median_radius_m) {
      best.base_rad = base;
      best.smooth_factor = factor;
      best.coverage = static_cast<double>(covered) / static_cast<double>(n);
      best.median_radius_m = median;
    }
  }
  return best;
}

void measure_allowance(const std::vector<CalibrationSample>& references, const CalibrationOptions& options,
                       AntennaCalibration& calibration) {
  AntennaCalibration applied = calibration;
  applied.allowance_base_rad = applied.allowance_smooth_factor = std::numeric_limits<double>::quiet_NaN();
  std::vector<AllowanceSample> found(references.size());
  std::vector<char> usable(references.size(), 0);
  // The antenna's own references, localized without any calibration too (AntennaCalibration::
  // reference_median_error_uncalibrated_m): NaN where either fit failed.
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> error_with(references.size(), kNaN), error_without(references.size(), kNaN);
#pragma omp parallel for schedule(dynamic)
  for (long i = 0; i < static_cast<long>(references.size()); ++i) {
    const CalibrationSample& ref = references[i];
    TagReads mine;
    mine.tag = ref.reads.tag;
    double farthest_m = 0.0;
    for (const ReadGroup& g : ref.reads.groups)
      if (g.antenna == calibration.antenna) {
        mine.groups.push_back(g);
        for (const PhaseRead& r : g.reads) farthest_m = std::max(farthest_m, (r.antenna_m - ref.tag_m).norm());
      }
    if (mine.read_count() == 0) continue;
    LocalizeOptions o;
    o.calibration = applied;
    o.fold_pi = options.fold_pi;
    o.height_known = options.planar;
    o.tag_height_m = ref.tag_m.z();
    o.mirror_prior = MirrorPrior::kPoint;  // the side is known here: the truth
    o.prior_point = ref.tag_m;
    o.max_range_m = std::max(1.0, 1.5 * farthest_m);
    o.systematic_phase_rad = 0.0;  // the radius without any allowance: its parts are what is measured
    o.smooth_misfit_factor = 0.0;
    o.max_uncertainty_m = o.max_residual_rad = std::numeric_limits<double>::max();
    o.max_outlier_fraction = 1.0;
    const LocalizeResult r = localize_nlls(mine, o);
    if (r.status() == Status::kFailed || !std::isfinite(r.radius_statistical_m) || !std::isfinite(r.radius_bias_m_per_rad))
      continue;
    found[i] = {(r.position - ref.tag_m).norm(), r.radius_statistical_m, r.radius_bias_m_per_rad, r.smooth_residual_rad};
    usable[i] = 1;
    if (!ref.fit_geometry) continue;
    o.calibration.reset();
    const LocalizeResult u = localize_nlls(mine, o);
    if (u.status() == Status::kFailed) continue;
    error_with[i] = found[i].error_m;
    error_without[i] = (u.position - ref.tag_m).norm();
  }
  std::vector<double> with, without;
  for (size_t i = 0; i < references.size(); ++i)
    if (std::isfinite(error_with[i]) && std::isfinite(error_without[i]))
      with.push_back(error_with[i]), without.push_back(error_without[i]);
  if (with.size() >= 10) {
    calibration.reference_median_error_m = summarize(with, 0, {}).median_error_m;
    calibration.reference_median_error_uncalibrated_m = summarize(without, 0, {}).median_error_m;
    calibration.reference_error_tags = static_cast<int>(with.size());
  }
  std::vector<AllowanceSample> samples;
  for (size_t i = 0; i < found.size(); ++i)
    if (usable[i]) samples.push_back(found[i]);
  if (samples.size() < 10) return;
  const Allowance a = choose_allowance(samples, options.allowance_coverage);
  if (!std::isfinite(a.median_radius_m)) return;
  calibration.allowance_base_rad = a.base_rad;
  calibration.allowance_smooth_factor = a.smooth_factor;
  calibration.allowance_samples = a.samples;
  calibration.allowance_coverage = a.coverage;
}

}  // namespace rfidray::loc
