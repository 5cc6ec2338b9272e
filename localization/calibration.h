#pragma once
// Calibration of one antenna from reference tags at known positions (antenna_calibration.h has the model).
// Input: samples = one tag's reads in one run with its true position. Unknowns: the phase-centre offset δ
// (antenna frame, 3), the carrier offsets c_f relative to the first (lowest) carrier, the pattern
// coefficients β, and one nuisance offset ν per sample (tag × run: the tag's own reflection phase), which is
// eliminated in closed form (angle of Σ w e^{j(φ − c_f − kR − pattern)}). Stops are reduced to circular
// means as in joint_model.h. Levenberg–Marquardt on the weighted wrapped residuals with a Gaussian prior
// (δ ~ N(0, prior_offset_sd_m²), β ~ N(0, prior_pattern_sd_rad²)): the offset and the pattern are nearly
// aliased (δ·u is itself a smooth function of direction; only the δ²/R curvature and the carrier slope tell
// them apart), so the prior keeps the split finite and the stated sd honest about it; the prediction
// (their sum) is what localization uses and is well determined.
// sd = sqrt(diag(s² ρ (JᵀWJ + P)⁻¹)), s² = max(1, χ²/dof), ρ the lag-1 autocorrelation factor (joint_fit.h).
// What the reference geometry cannot tell is not fitted (CalibrationOptions: planarity, Jacobian columns) and
// is listed with the reason in AntennaCalibration::not_fitted.
// Throws InputError when the samples hold no reads of `antenna` or fewer than 2 samples.
#include <string>
#include <vector>

#include "localization/antenna_calibration.h"
#include "localization/observations.h"

namespace rfidray::loc {

struct CalibrationSample {
  TagReads reads;     // one tag in one run
  Vec3 tag_m = Vec3::Zero();
  // false: used only to measure the radius allowance (allowance.h), not to fit the antenna — reference tags of
  // other setups (denser rows, other rooms) the antenna will be used in, whose own misfit would bend its model.
  bool fit_geometry = true;
  // Which run (readings file pair) it came from: the held-out check leaves one run out at a time.
  int run = 0;
};

struct CalibrationOptions {
  double stop_tolerance_m = 1e-3;
  double read_sigma_rad = 0.1;
  double floor_sigma_rad = 0.02;
  bool fold_pi = false;
  bool planar = false;              // antenna and tags in one horizontal plane: elevation terms and δ_z held 0
  // Geometry checks (whatever `planar` says): when every tag and antenna position lies within
  // planar_tolerance_m of one plane (RMS), the phase-centre offset normal to it changes each range only to
  // second order and not by its sign, so it is held at 0 (and the elevation terms too when that plane contains
  // the antenna's boresight and y axis: el ≡ 0); a parameter whose Jacobian column (scaled by its prior sd) is
  // below min_relative_information of the largest is held at 0 as well. Both are listed in not_fitted.
  double planar_tolerance_m = 0.02;
  double min_relative_information = 1e-3;
  // A fitted parameter whose sd exceeds this fraction of its prior sd is listed in prior_bounded.
  double prior_bounded_fraction = 0.7;
  // Two fitted geometry terms whose correlation exceeds this in magnitude are listed in aliased.
  double aliased_correlation = 0.98;
  // Radius evidence: localize every reference tag (NLLS, joint fit, gates open) with the fitted calibration and
  // measure the allowance (AntennaCalibration::allowance_*). Needs `planar` or tags off the path's plane.
  bool measure_allowance = true;
  double allowance_coverage = 0.95;
  // Whether the calibration helps tags it was not fitted on: cross-validation over runs in held_out_folds folds
  // (allowance.h, measure_held_out; AntennaCalibration::held_out_*). Needs reference tags from ≥ 2 runs; costs
  // one more calibration per fold (2 runs: leave one out; 5 or more: each fold a fifth of the runs).
  bool held_out_check = true;
  int held_out_folds = 5;
  // Which geometry terms to fit. false: held at 0 (with fit_offset, all three offsets).
  bool fit_pattern = true;
  bool fit_offset = true;
  // false (with fit_pattern and fit_offset false): nothing is calibrated — every carrier keeps its own offset, as
  // localize does without an antenna file (frequencies_hz left empty) — and only the allowance is measured.
  bool fit_carriers = true;
  // Choose the terms by the held-out check (needs held_out_check and reference tags from ≥ 2 runs): the nested
  // models — what fit_pattern / fit_offset allow, then the pattern held at 0, then the phase-centre offset too
  // (carrier offsets only), then nothing (fit_carriers false: its held-out error is the uncalibrated one of the
  // same check) — are each cross-validated, and the one with the lowest held-out median error is kept (the
  // simpler on a tie). The offset and the pattern are nearly aliased (both curve the wavefront; on the
  // AdaRF D1 runs dx and az² correlate at −0.995), so together they fit each run's own range bias — the tag
  // row's, the room's — which the next run does not share. Terms dropped are listed in not_fitted with the
  // held-out medians; every model tried in held_out_models. Costs a cross-validation per model (≤ 3).
  bool select_terms = true;
  double prior_offset_sd_m = 0.05;
  double prior_pattern_sd_rad = 1.0;
  int max_iterations = 100;
};

AntennaCalibration calibrate_antenna(const std::vector<CalibrationSample>& samples, const std::string& antenna,
                                     const CalibrationOptions& options = {});

// The choice of select_terms: of nested models' held-out median errors, richest first (NaN: not measured), the index
// of the lowest — the later (simpler) one on a tie; an unmeasured model is never chosen unless all are (then 0).
size_t model_with_lowest_held_out_error(const std::vector<double>& held_out_median_error_m);

}  // namespace rfidray::loc
