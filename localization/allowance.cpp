#include "localization/allowance.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>

#include "core/error.h"
#include "core/units.h"
#include "localization/calibration.h"
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
    double base = sorted[std::min(n, std::max<size_t>(need, 1)) - 1];
    if (!std::isfinite(base)) continue;
    // stat + ((error − stat) / bias) · bias can round below error: the sample that sets the base would then
    // fall outside its own radius by an ulp. 1e-12 rad (< 1e-12 m of radius) keeps it inside.
    if (base > 0.0) base += 1e-12;
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

namespace {

// One reference tag's reads of `antenna`, localized as the allowance and the held-out check localize it: NLLS,
// joint fit, the side known (the truth as prior point), every gate open, no allowance; `calibration` null: none.
// False when the tag has no reads of the antenna or the fit failed.
bool localize_reference(const CalibrationSample& ref, const std::string& antenna, const AntennaCalibration* calibration,
                        const CalibrationOptions& options, LocalizeResult& out) {
  TagReads mine;
  mine.tag = ref.reads.tag;
  double farthest_m = 0.0;
  for (const ReadGroup& g : ref.reads.groups)
    if (g.antenna == antenna) {
      mine.groups.push_back(g);
      for (const PhaseRead& r : g.reads) farthest_m = std::max(farthest_m, (r.antenna_m - ref.tag_m).norm());
    }
  if (mine.read_count() == 0) return false;
  LocalizeOptions o;
  if (calibration) o.calibration = *calibration;
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
  out = localize_nlls(mine, o);
  return out.status() != Status::kFailed;
}

}  // namespace

std::vector<double> uncalibrated_errors(const std::vector<CalibrationSample>& references, const std::string& antenna,
                                        const CalibrationOptions& options) {
  std::vector<double> error(references.size(), std::numeric_limits<double>::quiet_NaN());
#pragma omp parallel for schedule(dynamic)
  for (long i = 0; i < static_cast<long>(references.size()); ++i) {
    LocalizeResult u;
    if (references[i].fit_geometry && localize_reference(references[i], antenna, nullptr, options, u))
      error[i] = (u.position - references[i].tag_m).norm();
  }
  return error;
}

void measure_allowance(const std::vector<CalibrationSample>& references, const CalibrationOptions& options,
                       const std::vector<double>& uncalibrated_error_m, AntennaCalibration& calibration) {
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
    LocalizeResult r;
    if (!localize_reference(ref, calibration.antenna, &applied, options, r)) continue;
    if (!std::isfinite(r.radius_statistical_m) || !std::isfinite(r.radius_bias_m_per_rad)) continue;
    found[i] = {(r.position - ref.tag_m).norm(), r.radius_statistical_m, r.radius_bias_m_per_rad, r.smooth_residual_rad};
    usable[i] = 1;
    if (!ref.fit_geometry || !std::isfinite(uncalibrated_error_m[i])) continue;
    error_with[i] = found[i].error_m;
    error_without[i] = uncalibrated_error_m[i];
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
  // σ_sys chosen on the usable samples `in` keeps (none: fewer than 10 of them, or no finite choice).
  auto choose_on = [&](auto&& in) -> std::optional<Allowance> {
    std::vector<AllowanceSample> chosen;
    for (size_t i = 0; i < found.size(); ++i)
      if (usable[i] && in(i)) chosen.push_back(found[i]);
    if (chosen.size() < 10) return std::nullopt;
    const Allowance a = choose_allowance(chosen, options.allowance_coverage);
    if (!std::isfinite(a.median_radius_m)) return std::nullopt;
    return a;
  };
  const std::optional<Allowance> pooled = choose_on([](size_t) { return true; });
  if (!pooled) return;
  calibration.allowance_base_rad = pooled->base_rad;
  calibration.allowance_smooth_factor = pooled->smooth_factor;
  calibration.allowance_samples = pooled->samples;
  calibration.allowance_coverage = pooled->coverage;

  // The same per band of tag spacing (AntennaCalibration::allowance_bands), split at half the wavelength of the
  // lowest carrier the references were read on.
  const std::vector<double> spacing = nearest_neighbour_spacing_m(references);
  double lowest_hz = std::numeric_limits<double>::infinity();
  for (const CalibrationSample& ref : references)
    for (const ReadGroup& g : ref.reads.groups)
      if (g.antenna == calibration.antenna && !g.reads.empty()) lowest_hz = std::min(lowest_hz, g.frequency_hz);
  const double half_wavelength_m = 0.5 * wavelength_m(lowest_hz);
  calibration.allowance_bands.clear();
  for (const auto& [from_m, below_m] : {std::pair{0.0, half_wavelength_m},
                                        std::pair{half_wavelength_m, std::numeric_limits<double>::infinity()}}) {
    AntennaCalibration::AllowanceBand band;
    band.spacing_from_m = from_m;
    band.spacing_below_m = below_m;
    const std::optional<Allowance> b = choose_on([&](size_t i) { return band.contains(spacing[i]); });
    if (!b) continue;
    band.base_rad = b->base_rad;
    band.smooth_factor = b->smooth_factor;
    band.samples = b->samples;
    band.coverage = b->coverage;
    calibration.allowance_bands.push_back(band);
  }
}

std::vector<double> nearest_neighbour_spacing_m(const std::vector<CalibrationSample>& references) {
  std::vector<double> spacing(references.size(), std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < references.size(); ++i)
    for (size_t j = 0; j < references.size(); ++j)
      if (j != i && references[j].run == references[i].run && references[j].reads.tag != references[i].reads.tag)
        spacing[i] = std::min(spacing[i], (references[j].tag_m - references[i].tag_m).norm());
  return spacing;
}

void measure_held_out(const std::vector<CalibrationSample>& samples, const CalibrationOptions& options,
                      const std::vector<double>& uncalibrated_error_m, AntennaCalibration& calibration) {
  std::vector<int> runs;
  for (const CalibrationSample& s : samples)
    if (s.fit_geometry) runs.push_back(s.run);
  if (runs.size() < 10) return;  // fewer reference tags than the 10 the medians need: no fold is worth fitting
  std::sort(runs.begin(), runs.end());
  runs.erase(std::unique(runs.begin(), runs.end()), runs.end());
  if (runs.size() < 2 || options.held_out_folds < 2) return;
  // Runs dealt to folds in order (run i of the sorted list to fold i mod k): deterministic, and consecutive runs,
  // often alike, land in different folds.
  const int k = std::min<int>(options.held_out_folds, static_cast<int>(runs.size()));
  auto fold_of = [&](int run) {
    return static_cast<int>(std::lower_bound(runs.begin(), runs.end(), run) - runs.begin()) % k;
  };
  CalibrationOptions fit = options;  // each fold's calibration is what calibrate_antenna fits, nothing measured
  fit.measure_allowance = false;
  fit.held_out_check = false;
  std::vector<double> with, without;
  int folds = 0;
  for (int fold = 0; fold < k; ++fold) {
    std::vector<CalibrationSample> train;
    std::vector<size_t> test;  // indices into samples
    for (size_t i = 0; i < samples.size(); ++i)
      if (samples[i].fit_geometry) {
        if (fold_of(samples[i].run) == fold)
          test.push_back(i);
        else
          train.push_back(samples[i]);
      }
    AntennaCalibration c;
    try {
      c = calibrate_antenna(train, calibration.antenna, fit);
    } catch (const InputError&) {
      continue;  // the other runs have no reads of this antenna, or too few tags: no fold
    }
    ++folds;
    constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
    std::vector<double> e_with(test.size(), kNaN);
#pragma omp parallel for schedule(dynamic)
    for (long i = 0; i < static_cast<long>(test.size()); ++i) {
      const CalibrationSample& ref = samples[test[i]];
      LocalizeResult r;
      if (std::isfinite(uncalibrated_error_m[test[i]]) && localize_reference(ref, calibration.antenna, &c, options, r))
        e_with[i] = (r.position - ref.tag_m).norm();
    }
    for (size_t i = 0; i < test.size(); ++i)
      if (std::isfinite(e_with[i])) with.push_back(e_with[i]), without.push_back(uncalibrated_error_m[test[i]]);
  }
  if (folds < 2 || with.size() < 10) return;
  calibration.held_out_runs = static_cast<int>(runs.size());
  calibration.held_out_folds = folds;
  calibration.held_out_tags = static_cast<int>(with.size());
  calibration.held_out_median_error_m = summarize(with, 0, {}).median_error_m;
  calibration.held_out_median_error_uncalibrated_m = summarize(without, 0, {}).median_error_m;
}

}  // namespace rfidray::loc
