#pragma once
// Fitting the joint multi-carrier model (joint_model.h) at one start and judging the result honestly.
//
// Fit: LM on the weighted wrapped residuals, three rounds of Cauchy-reweighted LM (robust to a run of bad
// stops), then stops whose normalised residual |√w e| exceeds outlier_sigmas · max(σ̂, 1) are trimmed
// (σ̂ = 1.4826 · MAD) and LM runs again on the rest.
//
// Uncertainty (uncertainty_m = radius of the 95 % confidence region in the estimated coordinates):
//   Cov_LS = s² · ρ · (JᵀWJ)⁻¹, s² = max(1, Σ w e² / (n − dof − groups)): the weights already hold the
//     measured per-stop dispersion and the model floor, so s² < 1 is not believed;
//     ρ = Var(Σ r)/Σ r², the design effect of correlated residuals, estimated on the per-stop residual sums
//     (all carriers of one antenna position move together) with their autocorrelation along the aperture
//     summed to the first non-positive lag (n / n_eff);
//   Cov_JK = (B−1)/B Σ_b (p_b − p̄)(p_b − p̄)ᵀ, p_b re-fitted without the b-th of B contiguous aperture
//     blocks (delete-one-block jackknife).
//   Cov_cal = G Σ_β Gᵀ, G = (JᵀWJ)⁻¹ JᵀW K, K = ∂φ/∂β: the antenna calibration's covariance Σ_β of its
//     phase centre and pattern (antenna_calibration.h) carried to the position (with a calibration only);
//   radius = sqrt( max( χ²_{d,0.95} λ_max(Cov_LS), T²_{d,B−1,0.95} λ_max(Cov_JK) ) + χ²_{d,0.95} λ_max(Cov_cal) )
//            + σ_sys sqrt(N λ_max((J_uᵀJ_u)⁻¹))   (bias bound of an unmodelled smooth phase error of RMS
//              σ_sys = the largest of options.systematic_phase_rad, the fit's smooth misfit and the known
//              scene's multipath allowance at the estimate (multipath_allowance.h): an error the fit absorbs
//              and the residuals cannot show).
// Why both: systematic model error (multipath ripple, an uncalibrated pattern) is correlated over a good part
// of the aperture; the design effect sees it only up to the first sign change, while the block jackknife sees
// any error that changes along the aperture (it re-fits with each part missing) but is itself noisy with
// B = 10 blocks — hence its Hotelling T² quantile d(B−1)/(B−d) F_{d,B−d} instead of χ²_d, and the larger
// of the two radii.
//
// Judgement (status ok only when all hold):
//   (a) consistent: robust σ of the wrapped residuals ≤ max_residual_rad and trimmed fraction ≤
//       max_outlier_fraction (else inconsistent residuals);
//   (b) unique: every other local optimum c (the mirror across the path re-converged, plus the method's
//       other candidates) outside the region (farther than max(radius, λ/4)) has
//       Δχ² = (C(c) − C(p̂)) / (s² ρ) ≥ unique_chi2 — a likelihood-ratio test with the inflated variance, so
//       correlated residuals do not make a rival look worse than it is. A rival mirror is settled by the
//       mirror prior when one is given (then the fit is redone there), else ambiguous mirror. Other rivals
//       (reason undersampled when the median antenna step is > λ/4: grating lobes, else ambiguous peak) are
//       weighed (weigh_rivals) when the fit can be trusted to weigh them:
//         trusted: robust σ̂ of the wrapped residuals ≤ π / outlier_sigmas and trimmed fraction ≤
//           max_outlier_fraction. Δχ² is −2 log of the likelihood ratio only while the residuals are the
//           Gaussian the cost assumes; the fit keeps residuals out to outlier_sigmas·σ̂ as data, and that band
//           must not reach ±π, where a residual and its 2π alias are the same read (at σ̂ = 1.7 rad, 1 rad of
//           read noise with cycle slips, the truth was at neither optimum). The rivals are costed on the stops
//           the best fit kept, so it must not have discarded more than (a) allows.
//         then uncertain, never failed: with Laplace's odds o_c = exp(−Δχ²_c/2) (equal curvature and prior),
//           the rivals hold Σo / (1 + Σo) of the posterior; the region grows to enclose the most probable
//           rivals, each with the optimum's own radius, until the mass left outside is ≤ 5 % (one rival:
//           enclosed when Δχ² < 2 ln 19 ≈ 5.89), and the detail names the most probable rival and that mass
//           (a grown radius wider than the search region still fails as not located). On held-out AdaRF
//           training runs every rival fit had σ̂ 0.35–1.03 rad (s² of 500–1800: the inflation, not s² ≈ 1, is
//           what makes their Δχ² honest), so the gate removes none of them;
//         else failed (no position);
//   (c) radius ≤ max_uncertainty_m (else multipath when the known scene's allowance set σ_sys, else aperture
//       too short when the path is seen under < 60°, else phase too noisy).
#include <limits>
#include <vector>

#include "localization/joint_model.h"
#include "localization/prepare.h"

namespace rfidray::loc {

struct JointFit {
  Vec3 position = Vec3::Zero();
  bool converged = false;
  std::vector<double> mask;        // 1: inlier stop, 0: trimmed
  int outliers = 0;
  double cost = 0.0;               // Σ w e² over inliers
  double scale2 = 1.0;             // s²
  double inflation = 1.0;          // ρ
  double residual_rad = 0.0;       // robust σ of the unweighted wrapped residuals (inliers)
  double smooth_residual_rad = 0.0;  // RMS of their smooth part: √(lag-1 autocovariance in time order, ≥ 0)
  double multipath_phase_rad = std::numeric_limits<double>::quiet_NaN();  // known-scene allowance at position
  double calibration_radius_m = 0.0;  // sqrt(χ²_{d,0.95} λ_max(Cov_cal)); 0 without a calibration
  double statistical_radius_m = 0.0;  // the radius before the bias bound (noise, jackknife, calibration)
  double bias_m_per_rad = 0.0;        // sqrt(N λ_max((J_uᵀJ_u)⁻¹)): the bias bound per rad of smooth error
  double systematic_rad = 0.0;        // σ_sys the bias bound used
  double radius_m = 0.0;
  double predicted_std_m = 0.0;    // sqrt(trace Cov_LS)
};

// The coherence peak (joint_model.h) near `start`: 5×5(×5) local grids of spacing `step_m`, moved to their best
// point until it is the centre, then halved while the step is ≥ `min_step_m`. Puts a wrapped-phase fit into
// the right fringe: Levenberg–Marquardt converges from anywhere well inside it (a 5 mm start error is
// k·5 mm ≈ 0.2 rad of phase at 920 MHz), so a fit's start needs no finer step than about λ/64.
Vec3 focus_near(const JointModel& model, Vec3 start, double step_m, bool planar, double min_step_m);
// λ/64 of the model's shortest wavelength: the finest focus a start of `joint_lm` needs.
double focus_min_step_m(const JointModel& model);

JointModel make_joint_model(const TagReads& tag, const LocalizeOptions& options);
JointFit fit_joint(const JointModel& model, const Vec3& start, const LocalizeOptions& options);

// Another local optimum of the joint cost (not the mirror) outside the region, within unique_chi2.
struct RivalOptimum {
  Vec3 position = Vec3::Zero();
  double delta_chi2 = 0.0;  // (C(rival) − C(p̂)) / (s² ρ) on the best fit's inlier stops
};
struct RivalVerdict {
  bool trusted = false;             // the fit's residuals allow Δχ² to be read as log odds (judgement (b))
  double rival_mass = 0.0;          // Σ o / (1 + Σ o), o = exp(−Δχ²/2): the rivals' share of the posterior
  int enclosed = 0;                 // rivals (most probable first) the region grew to enclose
  double radius_m = 0.0;            // the region's radius after that
  std::vector<RivalOptimum> rivals;  // by increasing Δχ²
};
// Judgement (b) for rivals within unique_chi2 of the reported `position` (radius `radius_m`; the joint
// optimum's own radius `optimum_radius_m` is given to each enclosed rival).
RivalVerdict weigh_rivals(std::vector<RivalOptimum> rivals, const Vec3& position, double radius_m,
                          double optimum_radius_m, double residual_rad, double outlier_fraction,
                          const LocalizeOptions& options);

// Sets uncertainty_m / residual_rad / outliers / predicted_std_m and judges result (already ok, with a
// position) against (a)–(c). `rivals`: starts of other local optima to test (re-converged here).
// report_own_position: keep result.position (e.g. the hyperbolic cluster mode), the radius then grows by its
// distance to the joint optimum.
void judge_joint(LocalizeResult& result, const JointModel& model, JointFit fit, const std::vector<Vec3>& rivals,
                 const PreparedTag& prep, const LocalizeOptions& options, bool report_own_position = false);

}  // namespace rfidray::loc
