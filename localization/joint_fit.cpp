#include "localization/joint_fit.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <tuple>
#include <sstream>

#include "core/units.h"
#include "localization/mirror.h"

namespace rfidray::loc {

namespace {

double chi2_95(int d) { return d == 2 ? 5.991464547 : 7.814727903; }

// F_{d,ν,0.95} for d = 2, 3 (tables), linear in 1/ν between the tabulated ν.
double f_95(int d, int nu) {
  static const int kNu[] = {2, 3, 4, 5, 6, 7, 8, 9, 10, 12, 15, 20, 30, 60};
  static const double kF2[] = {19.00, 9.55, 6.94, 5.79, 5.14, 4.74, 4.46, 4.26, 4.10, 3.89, 3.68, 3.49, 3.32, 3.15};
  static const double kF3[] = {19.16, 9.28, 6.59, 5.41, 4.76, 4.35, 4.07, 3.86, 3.71, 3.49, 3.29, 3.10, 2.92, 2.76};
  const double* f = d == 2 ? kF2 : kF3;
  const double f_inf = d == 2 ? 2.996 : 2.605;
  if (nu <= 2) return f[0];
  for (int i = 1; i < 14; ++i)
    if (nu <= kNu[i]) {
      const double a = 1.0 / kNu[i - 1], b = 1.0 / kNu[i], x = 1.0 / nu;
      return f[i - 1] + (f[i] - f[i - 1]) * (x - a) / (b - a);
    }
  const double a = 1.0 / 60.0, x = 1.0 / nu;
  return f_inf + (f[13] - f_inf) * x / a;
}

double median_abs(std::vector<double> v) {
  if (v.empty()) return 0.0;
  for (double& x : v) x = std::abs(x);
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double lambda_max(const Eigen::MatrixXd& C) {
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(C);
  return es.eigenvalues().maxCoeff();
}

bool in_region(const Vec3& x, const PreparedTag& prep) {
  const double tol = 1e-6;
  return x.allFinite() && !(x.array() < prep.region_min.array() - tol).any() &&
         !(x.array() > prep.region_max.array() + tol).any();
}

}  // namespace

double focus_min_step_m(const JointModel& model) { return model.min_wavelength_m() / 64.0; }

Vec3 focus_near(const JointModel& m, Vec3 x, double step, bool planar, double min_step_m) {
  double best = m.coherence(x);
  while (step >= min_step_m) {
    bool moved = false;
    Vec3 best_x = x;
    const int zr = planar ? 0 : 2;
    for (int dz = -zr; dz <= zr; ++dz)
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          if (dx == 0 && dy == 0 && dz == 0) continue;
          const Vec3 c = x + step * Vec3(dx, dy, dz);
          const double s = m.coherence(c);
          if (s > best) best = s, best_x = c, moved = true;
        }
    x = best_x;
    if (!moved) step *= 0.5;
  }
  return x;
}

JointModel make_joint_model(const TagReads& tag, const LocalizeOptions& options) {
  JointModelOptions mo;
  mo.stop_tolerance_m = options.stop_tolerance_m;
  mo.read_sigma_rad = options.read_sigma_rad;
  mo.floor_sigma_rad = options.floor_sigma_rad;
  mo.fold_pi = options.fold_pi;
  mo.calibration = options.calibration ? &*options.calibration : nullptr;
  return JointModel(tag, mo, options.height_known, options.tag_height_m);
}

JointFit fit_joint(const JointModel& model, const Vec3& start, const LocalizeOptions& options) {
  JointFit fit;
  const int n = model.point_count(), d = model.dof();
  fit.mask.assign(n, 1);
  JointLm lm = joint_lm(model, start, options.lm_max_iterations);
  // Robust: three rounds of iteratively reweighted LM with Cauchy weights 1 / (1 + (r / 2.385 σ̂)²)
  // (σ̂ = 1.4826 MAD of the normalised residuals), so a contiguous run of bad stops (a shadowed or
  // coupled part of the aperture) cannot pull the fit; then stops beyond outlier_sigmas · max(σ̂, 1) are
  // trimmed (weight 0) and the rest re-fitted with their own weights.
  std::vector<double> robust_w(n, 1.0);
  double robust = 0.0;
  for (int round = 0; round < 4; ++round) {
    Eigen::VectorXd r;
    model.evaluate(lm.position, r, nullptr);
    robust = std::max(1.4826 * median_abs(std::vector<double>(r.data(), r.data() + n)), 1e-12);
    if (round == 3) break;
    for (int i = 0; i < n; ++i) robust_w[i] = 1.0 / (1.0 + std::pow(r[i] / (2.385 * robust), 2));
    lm = joint_lm(model, lm.position, options.lm_max_iterations, &robust_w);
  }
  {
    Eigen::VectorXd r;
    model.evaluate(lm.position, r, nullptr);
    const double limit = options.outlier_sigmas * std::max(robust, 1.0);
    for (int i = 0; i < n; ++i)
      if (std::abs(r[i]) > limit) fit.mask[i] = 0, ++fit.outliers;
    if (fit.outliers < n) lm = joint_lm(model, lm.position, options.lm_max_iterations, &fit.mask);
  }
  fit.position = lm.position;
  fit.converged = lm.converged;
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  model.evaluate(fit.position, r, &J, &fit.mask);
  fit.cost = r.squaredNorm();
  const int inliers = n - fit.outliers;
  const int dof_left = std::max(1, inliers - d - model.group_count());
  fit.scale2 = std::max(1.0, fit.cost / dof_left);
  // The inlier stops in time order (the aperture's order): the smooth-residual estimate and the jackknife
  // blocks both walk it.
  std::vector<int> by_time;
  for (int i = 0; i < n; ++i)
    if (fit.mask[i]) by_time.push_back(i);
  std::stable_sort(by_time.begin(), by_time.end(),
                   [&](int a, int b) { return model.points()[a].time_s < model.points()[b].time_s; });
  {
    std::vector<double> e = model.wrapped_residuals(fit.position), kept;
    for (int i = 0; i < n; ++i)
      if (fit.mask[i]) kept.push_back(e[i]);
    fit.residual_rad = 1.4826 * median_abs(kept);
    // The smooth part of the misfit (multipath off nearby objects, coupling, pattern residue) is what the
    // model cannot see; white read noise is not. Their variances separate in the lag-1 autocovariance of
    // the residuals in time order: ≈ σ_smooth² for an error that changes little from one stop to the next,
    // ≈ 0 for independent noise.
    double lag1 = 0.0;
    for (size_t k = 1; k < by_time.size(); ++k) lag1 += e[by_time[k]] * e[by_time[k - 1]];
    if (by_time.size() >= 2) lag1 /= static_cast<double>(by_time.size() - 1);
    fit.smooth_residual_rad = std::sqrt(std::max(0.0, lag1));
  }
  // Correlated residuals: inflation = Var(Σ r) / Σ r² (the design effect, n / n_eff), estimated on the
  // residual sums S_c of the antenna stops c (all carriers read at one antenna position: on real data their
  // residuals move together, multipath and pattern are nearly the same 0.5 % apart in frequency), in time
  // order: Var(Σ r) ≈ Σ_c S_c² + 2 Σ_k Σ_c S_c S_{c+k}, the lag sum cut at the first non-positive lag
  // (Geyer's initial positive sequence). A smooth systematic error along the aperture is correlated over
  // many stops, which a lag-1 coefficient alone would understate.
  {
    std::map<std::tuple<long, long, long>, int> cluster_of;
    std::vector<double> sum, time, count;
    double den = 0.0;
    const double q = std::max(options.stop_tolerance_m, 1e-6);
    for (int i = 0; i < n; ++i) {
      if (!fit.mask[i]) continue;
      const Vec3& a = model.points()[i].antenna_m;
      const auto key = std::make_tuple(std::lround(a.x() / q), std::lround(a.y() / q), std::lround(a.z() / q));
      auto [it, inserted] = cluster_of.try_emplace(key, static_cast<int>(sum.size()));
      if (inserted) sum.push_back(0.0), time.push_back(0.0), count.push_back(0.0);
      sum[it->second] += r[i];
      time[it->second] += model.points()[i].time_s;
      count[it->second] += 1.0;
      den += r[i] * r[i];
    }
    std::vector<int> order(sum.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return time[a] / count[a] < time[b] / count[b]; });
    double var = 0.0;
    for (double v : sum) var += v * v;
    const double lag0 = var;
    for (size_t lag = 1; lag0 > 0.0 && lag < order.size() / 2; ++lag) {
      double c = 0.0;
      for (size_t k = lag; k < order.size(); ++k) c += sum[order[k]] * sum[order[k - lag]];
      if (c <= 0.0) break;
      var += 2.0 * c;
    }
    fit.inflation = den > 0.0 ? std::clamp(var / den, 1.0, static_cast<double>(std::max(1, inliers))) : 1.0;
  }
  const Eigen::MatrixXd A = J.transpose() * J;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
  if (!lu.isInvertible()) {
    fit.radius_m = fit.predicted_std_m = std::numeric_limits<double>::infinity();
    return fit;
  }
  const Eigen::MatrixXd cov_ls = fit.scale2 * fit.inflation * lu.inverse();
  fit.predicted_std_m = std::sqrt(std::max(0.0, cov_ls.trace()));
  double radius2 = chi2_95(d) * std::max(0.0, lambda_max(cov_ls));

  // Delete-one-block jackknife over contiguous aperture blocks (by time).
  const std::vector<int>& order = by_time;
  const int blocks = std::min(options.jackknife_blocks, static_cast<int>(order.size()) / 5);
  if (blocks >= d + 2) {
    std::vector<Eigen::VectorXd> est;
    for (int b = 0; b < blocks; ++b) {
      std::vector<double> mask = fit.mask;
      const size_t lo = order.size() * b / blocks, hi = order.size() * (b + 1) / blocks;
      for (size_t k = lo; k < hi; ++k) mask[order[k]] = 0;
      const JointLm lb = joint_lm(model, fit.position, 20, &mask);
      est.push_back(model.to_unknowns(lb.position));
    }
    Eigen::VectorXd mean = Eigen::VectorXd::Zero(d);
    for (const auto& e : est) mean += e;
    mean /= blocks;
    Eigen::MatrixXd cov_jk = Eigen::MatrixXd::Zero(d, d);
    for (const auto& e : est) cov_jk += (e - mean) * (e - mean).transpose();
    cov_jk *= static_cast<double>(blocks - 1) / blocks;
    const double t2 = static_cast<double>(d) * (blocks - 1) / (blocks - d) * f_95(d, blocks - d);
    if (cov_jk.allFinite()) radius2 = std::max(radius2, t2 * lambda_max(cov_jk));
  }
  // The calibration's own uncertainty (its covariance Σ_β of phase centre and pattern) moves the estimate by
  // δu = −(JᵀJ)⁻¹ Jᵀ K δβ (K = ∂r/∂β): an independent error, so its covariance G Σ_β Gᵀ adds to the region's.
  if (options.calibration) {
    const Eigen::MatrixXd K = model.calibration_jacobian(fit.position, &fit.mask);
    const Eigen::MatrixXd G = lu.solve(J.transpose() * K);
    const Eigen::MatrixXd cov_cal = G * options.calibration->geometry_covariance_or_sd() * G.transpose();
    if (cov_cal.allFinite()) {
      fit.calibration_radius_m = std::sqrt(chi2_95(d) * std::max(0.0, lambda_max(cov_cal)));
      radius2 += fit.calibration_radius_m * fit.calibration_radius_m;
    }
  }
  fit.radius_m = std::sqrt(radius2);
  // Model-error allowance: an unmodelled smooth phase error ε of RMS σ_sys over the N inlier stops
  // (multipath off nearby objects, pattern residue) that happens to lie in the span of J shifts the estimate
  // by (J_uᵀJ_u)⁻¹J_uᵀε, at most σ_sys · sqrt(N λ_max((J_uᵀJ_u)⁻¹)) (Cauchy–Schwarz; J_u unweighted, rad/m).
  // It is invisible in the residuals (the fit absorbs it), so it is added as a bias bound, not averaged.
  // Its RMS is the larger of the allowance and (a multiple of) the smooth misfit measured in this fit's residuals
// (the fit absorbs part of a smooth error, so what is left understates it; the factor is measured with the
// allowance on reference tags by calibrate) (and, with
  // a known scene, of its multipath allowance: below).
  const double fixed_rad = std::max(options.systematic_phase_rad, options.smooth_misfit_factor * fit.smooth_residual_rad);
  double bias_m_per_rad = 0.0;
  {
    Eigen::MatrixXd Ju = J;
    for (int i = 0; i < n; ++i) {
      const double w = model.points()[i].weight * fit.mask[i];
      Ju.row(i) = w > 0.0 ? Eigen::RowVectorXd(J.row(i) / std::sqrt(w)) : Eigen::RowVectorXd::Zero(d);
    }
    Eigen::FullPivLU<Eigen::MatrixXd> lu_u(Ju.transpose() * Ju);
    bias_m_per_rad = lu_u.isInvertible() ? std::sqrt(inliers * std::max(0.0, lambda_max(lu_u.inverse())))
                                         : std::numeric_limits<double>::infinity();
  }
  const double stat_radius_m = fit.radius_m;
  fit.statistical_radius_m = stat_radius_m;
  fit.bias_m_per_rad = bias_m_per_rad;
  fit.systematic_rad = fixed_rad;
  auto radius_with = [&](double systematic_rad) {
    return systematic_rad > 0.0 ? stat_radius_m + systematic_rad * bias_m_per_rad : stat_radius_m;
  };
  fit.radius_m = radius_with(fixed_rad);
  // A known scene's allowance (multipath_allowance.h) depends on where the tag is, and the fit has already
  // moved by the bias it bounds: a wall 0.1 m behind a tag pulls the estimate towards it, where the image is
  // nearer and the allowance small (0.015 against 0.15 rad at the truth, 7 cm away). So the allowance is the
  // largest over the region it implies: at the estimate and on the region's boundary (8 directions in the
  // plane, 14 in 3-D), grown until the region no longer grows (a few rounds) or it is past any use.
  if (options.multipath_phase_rad && std::isfinite(fit.radius_m)) {
    double allowance = options.multipath_phase_rad(fit.position);
    std::vector<Vec3> directions;
    for (int i = 0; i < 8; ++i)
      directions.emplace_back(std::cos(kPi * i / 4.0), std::sin(kPi * i / 4.0), 0.0);
    if (!options.height_known) {
      directions.emplace_back(0.0, 0.0, 1.0), directions.emplace_back(0.0, 0.0, -1.0);
      for (int sx : {-1, 1})
        for (int sy : {-1, 1})
          for (int sz : {-1, 1}) directions.push_back(Vec3(sx, sy, sz).normalized());
    }
    for (int round = 0; round < 6 && std::isfinite(allowance); ++round) {
      const double reach_m = radius_with(std::max(fixed_rad, allowance));
      if (!(reach_m <= 2.0 * options.max_uncertainty_m)) break;  // failed whatever the boundary holds
      double boundary = allowance;
      // A boundary point no path reaches (behind a metal wall) is not where a tag that was read can be.
      for (const Vec3& u : directions) {
        const double a = options.multipath_phase_rad(fit.position + reach_m * u);
        if (std::isfinite(a)) boundary = std::max(boundary, a);
      }
      if (!(boundary > allowance)) break;
      allowance = boundary;
    }
    fit.multipath_phase_rad = allowance;
    fit.radius_m = radius_with(std::max(fixed_rad, allowance));
    fit.systematic_rad = std::max(fixed_rad, allowance);
  }
  if (!std::isfinite(fit.radius_m)) fit.radius_m = std::numeric_limits<double>::infinity();
  return fit;
}

RivalVerdict weigh_rivals(std::vector<RivalOptimum> rivals, const Vec3& position, double radius_m,
                          double optimum_radius_m, double residual_rad, double outlier_fraction,
                          const LocalizeOptions& options) {
  RivalVerdict v;
  std::stable_sort(rivals.begin(), rivals.end(),
                   [](const RivalOptimum& a, const RivalOptimum& b) { return a.delta_chi2 < b.delta_chi2; });
  v.rivals = std::move(rivals);
  v.radius_m = radius_m;
  // Δχ² is −2 log of the likelihood ratio only while the wrapped residuals are the Gaussian the cost assumes:
  // the fit keeps residuals out to outlier_sigmas·σ̂ as data, and that band must not reach ±π, where a residual
  // and its 2π alias are the same read. And the rivals are costed on the stops the best fit kept: it must not
  // have discarded more of them than (a) allows, or the comparison is made on data chosen to fit it.
  v.trusted = residual_rad <= kPi / options.outlier_sigmas && outlier_fraction <= options.max_outlier_fraction;
  double odds = 0.0;
  for (const RivalOptimum& r : v.rivals) odds += std::exp(-0.5 * r.delta_chi2);
  v.rival_mass = odds / (1.0 + odds);
  double left = odds;
  for (const RivalOptimum& r : v.rivals) {
    if (left / (1.0 + odds) <= 0.05) break;
    v.radius_m = std::max(v.radius_m, (r.position - position).norm() + optimum_radius_m);
    left -= std::exp(-0.5 * r.delta_chi2);
    ++v.enclosed;
  }
  return v;
}

constexpr const char* kNoPathDetail =
    "no path of the scene reaches the estimate from some of the antenna positions: its phase there is unknown";

void judge_joint(LocalizeResult& result, const JointModel& model, JointFit fit, const std::vector<Vec3>& rivals,
                 const PreparedTag& prep, const LocalizeOptions& options, bool report_own_position) {
  if (!result.ok) return;
  const double lambda4 = model.min_wavelength_m() / 4.0;
  auto apply_fit = [&](const JointFit& f) {
    const Vec3 own = result.position;
    result.position = report_own_position ? own : f.position;
    result.uncertainty_m = f.radius_m + (report_own_position ? (own - f.position).norm() : 0.0);
    result.radius_statistical_m = f.statistical_radius_m;
    result.radius_bias_m_per_rad = f.bias_m_per_rad;
    result.radius_systematic_rad = f.systematic_rad;
    result.smooth_residual_rad = f.smooth_residual_rad;
    result.residual_rad = f.residual_rad;
    result.multipath_phase_rad = f.multipath_phase_rad;
    result.outliers = f.outliers;
  };
  // No position (two optima fit equally, the prior excludes the fit, no path reaches it).
  auto fail = [&](FailReason reason, const std::string& why) { result.fail_without_position(reason, why); };
  // A position and its radius, not ok: the first such reason is kept, the checks that can still fail the
  // result go on (a rival optimum makes it failed whatever its misfit).
  FailReason soft_reason = FailReason::kNone;
  std::string soft_detail;
  auto not_ok = [&](FailReason reason, const std::string& why) {
    if (soft_reason == FailReason::kNone) soft_reason = reason, soft_detail = why;
  };
  // A rival that re-converges to a clearly lower cost than the start's optimum is the better answer: the fit
  // moves there (the hyperbolic cluster mode or the unwrapped start fell into a worse basin), once.
  {
    double best_cost = fit.cost;
    Vec3 best_at = fit.position;
    for (const Vec3& start : rivals) {
      if ((start - fit.position).norm() <= lambda4) continue;
      const JointLm c = joint_lm(model, start, options.lm_max_iterations, &fit.mask);
      if (!in_region(c.position, prep) || (c.position - fit.position).norm() <= lambda4) continue;
      const double cost = model.cost(c.position, &fit.mask);
      if (cost < best_cost - 1e-6 * fit.cost) best_cost = cost, best_at = c.position;
    }
    if (best_at != fit.position) {
      fit = fit_joint(model, best_at, options);
      result.position = fit.position;
      report_own_position = false;
    }
  }
  apply_fit(fit);
  if (std::isinf(fit.multipath_phase_rad)) {
    fail(FailReason::kMultipath, kNoPathDetail);
    return;
  }
  // LM only accepts cost decreases, so an iteration cap still leaves a point at least as good as its start;
  // its region comes from the residuals and the jackknife like any other.

  // (b) uniqueness.
  std::vector<Vec3> positions;
  std::vector<Quat> orientations;
  for (const JointPoint& p : model.points()) positions.push_back(p.antenna_m), orientations.push_back(p.orientation);
  auto delta_chi2 = [&](const JointFit& best, const Vec3& other) {
    return (model.cost(other, &best.mask) - best.cost) / (best.scale2 * best.inflation);
  };
  Vec3 mirror_at = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  {
    Vec3 reflected;
    if (!reflect_across_path(positions, options.height_known, fit.position, reflected)) {
      fail(FailReason::kAmbiguousMirror, "straight antenna path in 3-D: the tag can be anywhere on a circle around it");
      return;
    }
    const double sep = std::max(fit.radius_m, lambda4);
    if ((reflected - fit.position).norm() > sep) {
      const JointLm m = joint_lm(model, reflected, options.lm_max_iterations, &fit.mask);
      if (in_region(m.position, prep) && (m.position - fit.position).norm() > sep) {
        mirror_at = m.position;
        MirrorCheck check;
        check.mirror = m.position;
        check.delta_chi2 = delta_chi2(fit, m.position);
        check.ambiguous = check.delta_chi2 < options.unique_chi2;
        if (check.ambiguous) {
          const Vec3 before = result.position;
          result.position = fit.position;
          settle_mirror(result, check, positions, orientations, options);
          if (!result.ok) return;
          if ((result.position - fit.position).norm() > 0.0) {
            // The prior chose the other side: the fit (and its region) is redone there.
            mirror_at = fit.position;
            fit = fit_joint(model, result.position, options);
            report_own_position = false;
          } else {
            result.position = before;
          }
          apply_fit(fit);
        }
      }
    }
  }
  // The boresight prior says the tag is in front of the antenna. A fit behind it that its mirror could not
  // displace (the mirror fits worse by ≥ unique_chi2, e.g. because a calibrated pattern is extrapolated
  // behind the antenna) means the data and the prior disagree: no side can be reported with confidence.
  if (options.mirror_prior == MirrorPrior::kBoresight) {
    double cosine = 0.0;
    for (size_t i = 0; i < positions.size(); ++i)
      cosine += (orientations[i] * Vec3::UnitX()).dot((result.position - positions[i]).normalized());
    cosine /= std::max<size_t>(1, positions.size());
    if (cosine < 0.0) {
      std::ostringstream why;
      why << "the best fit (" << result.position.x() << ", " << result.position.y() << ", " << result.position.z()
          << ") lies behind the antenna (mean boresight cosine " << cosine << ") and --mirror-prior boresight "
          << "excludes it";
      fail(FailReason::kBehindAntenna, why.str());
      return;
    }
  }
  // (a) consistency (after the mirror is settled: a pattern makes the wrong side fit badly).
  const int n = model.point_count();
  if (fit.residual_rad > options.max_residual_rad) {
    std::ostringstream why;
    why << "wrapped-phase residual sigma " << fit.residual_rad << " rad > " << options.max_residual_rad << " rad";
    not_ok(FailReason::kInconsistentResiduals, why.str());
  }
  if (fit.outliers > options.max_outlier_fraction * n) {
    std::ostringstream why;
    why << fit.outliers << " of " << n << " stops are > " << options.outlier_sigmas << " sigma outliers";
    not_ok(FailReason::kInconsistentResiduals, why.str());
  }
  // Other optima within unique_chi2 (each re-converged; the same optimum reached from two starts counted once),
  // weighed by weigh_rivals (judgement (b) in the header).
  std::vector<RivalOptimum> found;
  const double sep = std::max(fit.radius_m, lambda4);
  for (const Vec3& start : rivals) {
    if ((start - fit.position).norm() <= sep) continue;
    const JointLm c = joint_lm(model, start, options.lm_max_iterations, &fit.mask);
    if (!in_region(c.position, prep)) continue;
    if ((c.position - fit.position).norm() <= sep) continue;
    if (mirror_at.allFinite() && (c.position - mirror_at).norm() <= sep) continue;
    const double dchi2 = delta_chi2(fit, c.position);
    if (dchi2 >= options.unique_chi2) continue;
    auto same = std::find_if(found.begin(), found.end(),
                             [&](const RivalOptimum& f) { return (f.position - c.position).norm() <= sep; });
    if (same == found.end())
      found.push_back({c.position, dchi2});
    else if (dchi2 < same->delta_chi2)
      *same = {c.position, dchi2};
  }
  if (!found.empty()) {
    const RivalVerdict v = weigh_rivals(found, result.position, result.uncertainty_m, fit.radius_m, fit.residual_rad,
                                        static_cast<double>(fit.outliers) / std::max(1, n), options);
    const RivalOptimum& near = v.rivals.front();
    std::ostringstream why;
    why << "another optimum at (" << near.position.x() << ", " << near.position.y() << ", " << near.position.z()
        << "), " << (near.position - fit.position).norm() << " m away, fits within " << near.delta_chi2
        << " chi2 units";
    const bool under = prep.median_step_m > lambda4;
    if (under) why << "; median read spacing " << prep.median_step_m << " m > lambda/4 (grating lobes)";
    const FailReason reason = under ? FailReason::kUndersampled : FailReason::kAmbiguousPeak;
    if (!v.trusted) {
      why << "; the fit cannot weigh them (wrapped residual sigma " << fit.residual_rad << " rad";
      if (fit.residual_rad > kPi / options.outlier_sigmas) why << " > pi/" << options.outlier_sigmas;
      why << ", " << fit.outliers << " of " << n << " stops trimmed)";
      fail(reason, why.str());
      return;
    }
    why << "; optima within " << options.unique_chi2 << " chi2 units: " << v.rivals.size()
        << ", their share of the posterior " << 100.0 * v.rival_mass << " %";
    if (v.enclosed > 0)
      why << ": the 95% radius is grown to enclose " << v.enclosed << " (" << v.radius_m << " m)";
    else
      why << " (<= 5 %): the radius is the best optimum's";
    result.uncertainty_m = v.radius_m;
    // The rival is what the user must know first; a misfit found by (a) follows in the detail.
    if (soft_reason != FailReason::kNone) why << "; " << soft_detail;
    soft_reason = reason, soft_detail = why.str();
  }
  // A 95 % region wider than the search region (every candidate lies within max_range_m of the antenna path)
  // tells the user nothing the search region did not: on held-out AdaRF training runs such fits had radii of
  // 4–13 000 m. No position rather than a point with a meaningless radius.
  if (!(result.uncertainty_m <= options.max_range_m)) {
    std::ostringstream why;
    why << "95% position uncertainty " << result.uncertainty_m << " m is wider than the search region (within "
        << options.max_range_m << " m of the antenna path): the reads do not locate the tag";
    fail(FailReason::kNotLocated, why.str());
    return;
  }
  // (c) size of the region.
  if (!(result.uncertainty_m <= options.max_uncertainty_m)) {
    const double angle = aperture_angle_deg(positions, result.position);
    std::ostringstream why;
    if (fit.multipath_phase_rad > std::max(options.systematic_phase_rad, options.smooth_misfit_factor * fit.smooth_residual_rad)) {
      if (std::isinf(fit.multipath_phase_rad)) {
        fail(FailReason::kMultipath, kNoPathDetail);
        return;
      }
      why << "the scene's extra paths bend the phase near the estimate by " << fit.multipath_phase_rad
          << " rad RMS along the aperture (a fit absorbs such an error without a trace in its residuals): 95% "
          << "position uncertainty " << result.uncertainty_m << " m > " << options.max_uncertainty_m << " m";
      not_ok(FailReason::kMultipath, why.str());
    } else {
      why << "95% position uncertainty " << result.uncertainty_m << " m > " << options.max_uncertainty_m
          << " m; path seen under " << angle << " deg, wrapped residual sigma " << fit.residual_rad << " rad";
      not_ok(angle < 60.0 ? FailReason::kApertureTooShort : FailReason::kNoisyPhase, why.str());
    }
  }
  if (soft_reason != FailReason::kNone) result.mark_not_ok(soft_reason, soft_detail);
}

}  // namespace rfidray::loc
