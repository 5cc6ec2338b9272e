#pragma once
// Options shared by the localization methods. Defaults are documented where they are chosen.
#include <functional>
#include <optional>

#include "core/geometry.h"
#include "localization/antenna_calibration.h"
#include "localization/phase_unwrap.h"

namespace rfidray::loc {

// How to settle a detected mirror ambiguity (straight path in 2-D, planar path in 3-D).
enum class MirrorPrior {
  kNone,       // report failed / ambiguous mirror
  kBoresight,  // keep the candidate in front of the antenna (local +X), averaged over the reads
  kPoint,      // keep the candidate nearer `prior_point` (e.g. the truth file: an oracle, documented as such)
};

struct LocalizeOptions {
  // 2-D case of the paper: antenna moves in a plane and the tag height is known (z fixed to tag_height_m).
  bool height_known = false;
  double tag_height_m = 0.0;

  UnwrapOptions unwrap;        // frequency is set per group
  int min_reads = 10;          // fewer usable reads → too few reads
  int min_segment_reads = 5;   // segments shorter than this carry no usable range difference
  double min_segment_extent_m = 0.01;   // segments whose antenna moved less carry no position information
  double min_aperture_m = 0.3;          // antenna path extent below this → aperture too short
  double min_aperture_angle_deg = 10.0; // path seen from the estimate under a smaller angle → too short
                                        // (cross-range resolution λ/(4 sin(θ/2)) > λ at 10°)
  double max_range_m = 10.0;   // search region: within this distance of the antenna positions

  // Mirror test: a distinct candidate whose fit is within this many χ² units of the best is ambiguous.
  double mirror_chi2 = 25.0;
  // Quality gates: a result whose predicted 1-σ position uncertainty exceeds max_std_m is failed (aperture
  // too short when the path is seen under < 60°, else phase too noisy); unwrapped methods also fail when
  // more than max_slip_fraction of the reads sit > 0.75π from the fit (a cycle slip shifts reads by 2π).
  double max_std_m = 0.02;
  double max_slip_fraction = 0.02;
  double noise_floor_m = 1e-4; // lower bound of the residual σ used by the χ² tests (quantisation level)
  MirrorPrior mirror_prior = MirrorPrior::kNone;
  Vec3 prior_point = Vec3::Zero();

  // Hyperbolic intersection (the paper's method).
  double stride_m = 0.10;      // new conic every antenna move ≥ stride (raised to keep ≤ max_conics)
  int max_conics = 100;
  double cluster_bandwidth_m = 0.05;

  // Levenberg–Marquardt.
  int lm_max_iterations = 100;

  // Joint multi-carrier model (joint_model.h) and its honest uncertainty (joint_fit.h).
  std::optional<AntennaCalibration> calibration;  // applied to the reads of its antenna (all if unnamed)
  bool fold_pi = false;            // the reader reports phase mod π: fit 2φ
  double stop_tolerance_m = 1e-3;  // reads within this antenna move form one stop (one circular mean)
  double read_sigma_rad = 0.1;     // per-read σ when a stop has one read
  double floor_sigma_rad = 0.02;   // model-error floor of each stop's σ
  // Model-error allowance (joint_fit.h): RMS of an unmodelled smooth phase error that the fit cannot see;
  // it enters uncertainty_m as a bias bound. Tuned on the AdaRF train split (real Impinj reads).
  double systematic_phase_rad = 0.1;  // callers without a user value: default_systematic_phase_rad() below
  // σ_sys = max(systematic_phase_rad, smooth_misfit_factor × the fit's own smooth misfit) (joint_fit.h). An
  // antenna file whose calibration measured both on its reference tags (AntennaCalibration::allowance_*) sets
  // them (localize_request.h: apply_calibration_allowance).
  double smooth_misfit_factor = 1.0;
  // Known-scene allowance (multipath_allowance.h): the RMS (rad) of the smooth phase error the scene's extra
  // paths add at a candidate tag position, over this tag's antenna positions. Set per tag by callers that know
  // the scene (`rfidray localize --scenario`); empty: none. Called from the localizing thread, a few times per
  // fit; must be deterministic. When it sets the radius above max_uncertainty_m the reason is multipath.
  std::function<double(const Vec3& tag_m)> multipath_phase_rad;
  double confidence = 0.95;        // of the uncertainty_m region (0.95 only: the quantiles are tabulated)
  int jackknife_blocks = 10;       // contiguous aperture blocks for the delete-one-block jackknife
  double max_residual_rad = 0.25;  // robust σ of the wrapped residuals above this → phase too noisy
  double max_outlier_fraction = 0.2;  // stops trimmed as > 3σ̂ outliers above this → phase too noisy
  double outlier_sigmas = 3.0;
  double max_uncertainty_m = 0.15; // a larger 95 % radius → failed (aperture too short / phase too noisy)
  // Uniqueness: another local optimum outside the confidence region whose cost is within unique_chi2 of the
  // best (in units of the inflated residual variance) makes the solution ambiguous: uncertain, its region grown
  // to enclose rivals holding > 5 % of the posterior, or failed when the fit cannot weigh them (joint_fit.h (b)).
  double unique_chi2 = 25.0;

  // SAR / holographic grid.
  double sar_coarse_step_fraction = 0.25;  // coarse grid step as a fraction of λ
  double sar_fine_step_m = 0.0005;         // stop refining below this step
  int sar_peaks = 8;                       // coarse peaks refined
};

// The model-error allowance when the user gives none. Without a calibration the antenna's own phase pattern
// is model error too: on the AdaRF D1 training split (42 held-out runs, 210 tags, README "Real readers"),
// uncalibrated, 0.1 rad left 4 of 35 ok NLLS results outside their radius (11 %), 0.2 rad none of 26;
// calibrated, 0.1 rad left none of 37 outside.
inline double default_systematic_phase_rad(bool calibrated) { return calibrated ? 0.1 : 0.2; }

}  // namespace rfidray::loc
