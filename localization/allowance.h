#pragma once
// The radius allowance measured on reference tags (the evidence behind AntennaCalibration::allowance_*).
//
// A localization's 95 % radius is a statistical radius plus a bias bound σ_sys · B (joint_fit.h), where σ_sys is
// the RMS of the smooth phase error the fit cannot see (the room's multipath, a tag's coupling to its
// neighbours, what the calibration left) and B = sqrt(N λ_max((J_uᵀJ_u)⁻¹)) the shift per rad such an error can
// cause. How large σ_sys is on a setup is not a property of the reader but of the room and the tag rows — so it
// is measured where the truth is known: every reference tag is localized (NLLS, joint fit, every gate open) with
// the calibration just fitted, and the pair (base, factor) of σ_sys = max(base, factor · smooth misfit of the
// fit) with the smallest median radius that puts ≥ `coverage` of the reference tags inside their radius is kept.
// The fit's own smooth misfit carries a tag's condition (a worse row, a worse residual) into its radius; the
// factor says how much of a smooth error a fit absorbs and leaves unseen.
//
// The reference tags also determined the calibration (8 geometry terms over all of them), so their errors are
// slightly optimistic. Pure function; throws nothing; runs the samples in parallel (deterministic).
#include <string>
#include <vector>

#include "localization/antenna_calibration.h"
#include "localization/calibration.h"

namespace rfidray::loc {

struct AllowanceSample {
  double error_m = 0.0;             // localized position − truth
  double statistical_radius_m = 0.0;
  double bias_m_per_rad = 0.0;
  double smooth_residual_rad = 0.0;
};

struct Allowance {
  double base_rad = 0.0;
  double smooth_factor = 1.0;
  double coverage = 0.0;            // share of the samples inside their radius
  double median_radius_m = 0.0;
  int samples = 0;
};

// The smallest-median-radius (base, factor) on a grid of factors (0 … 8) covering ≥ `coverage` of `samples`;
// samples.empty(): coverage 0, samples 0.
Allowance choose_allowance(const std::vector<AllowanceSample>& samples, double coverage);

// Each reference's position error localized without any calibration, as the two below localize it (NLLS, side
// known, gates open); NaN where the sample is not fit_geometry, has no reads of `antenna` or the fit failed. Computed
// once and shared by both (same `options`).
std::vector<double> uncalibrated_errors(const std::vector<CalibrationSample>& references, const std::string& antenna,
                                        const CalibrationOptions& options);

// Localizes every reference tag of `antenna` with `calibration` and fills its allowance_* fields (left NaN when
// fewer than 10 tags could be localized) and allowance_bands (choose_allowance on each band's tags), and reference_median_error_* from those also in `uncalibrated_error_m`
// (uncalibrated_errors of the same references and options).
void measure_allowance(const std::vector<CalibrationSample>& references, const CalibrationOptions& options,
                       const std::vector<double>& uncalibrated_error_m, AntennaCalibration& calibration);

// Each reference's distance to the nearest other tag of its run (CalibrationSample::run, any tag, fitting or
// not); infinity for a tag alone in its run. O(n²) in the references (a few hundred).
std::vector<double> nearest_neighbour_spacing_m(const std::vector<CalibrationSample>& references);

// Cross-validation over runs: the runs of the fitting references (CalibrationSample::run, fit_geometry) dealt to
// k = min(options.held_out_folds, runs) folds; for each fold, the antenna calibrated from the other folds' runs
// (calibrate_antenna with `options`, nothing measured), and the fold's reference tags localized as
// measure_allowance localizes them, with that calibration and without any. Fills held_out_* with the medians over
// all tags localized both ways; left unset with fewer than 2 folds that could be fitted or fewer than 10 such
// tags. Costs k calibrations.
// `uncalibrated_error_m`: uncalibrated_errors of `samples` with `options`.
void measure_held_out(const std::vector<CalibrationSample>& samples, const CalibrationOptions& options,
                      const std::vector<double>& uncalibrated_error_m, AntennaCalibration& calibration);

}  // namespace rfidray::loc
