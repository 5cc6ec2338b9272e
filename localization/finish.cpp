#include "localization/finish.h"

#include <cmath>
#include <sstream>

#include "core/units.h"

#include "localization/mirror.h"

namespace rfidray::loc {

void gate_uncertainty(LocalizeResult& result, const PreparedTag& prep, const RangeCost& cost, double sigma_m,
                      const LocalizeOptions& options, SoftGate* soft) {
  if (!result.ok) return;
  result.predicted_std_m = predicted_std_m(cost, result.position, std::max(sigma_m, options.noise_floor_m));
  if (result.predicted_std_m <= options.max_std_m) return;
  const double angle = aperture_angle_deg(prep.positions, result.position);
  std::ostringstream why;
  why << "predicted position uncertainty " << result.predicted_std_m << " m (1 sigma) > " << options.max_std_m
      << " m; path seen under " << angle << " deg, range noise " << sigma_m << " m per read";
  const FailReason reason = angle < 60.0 ? FailReason::kApertureTooShort : FailReason::kNoisyPhase;
  if (soft) {
    if (!soft->failed) *soft = SoftGate{true, reason, why.str()};
    return;
  }
  result.ok = false;
  result.reason = reason;
  result.detail = why.str();
}

void apply_soft_gate(LocalizeResult& result, const SoftGate& soft) {
  // The unwrapped fit's own finding (cycle slips, a weak geometry) names the cause better than a radius the
  // joint judgement found too large: it takes precedence whenever a position is reported.
  // A near rival optimum the joint judgement found stays named in the detail.
  if (soft.failed && result.status() != Status::kFailed) {
    const bool rival = result.reason == FailReason::kAmbiguousPeak || result.reason == FailReason::kUndersampled;
    result.mark_not_ok(soft.reason, rival ? soft.detail + "; " + result.detail : soft.detail);
  }
}

void finish_unwrapped(LocalizeResult& result, const PreparedTag& prep, const RangeCost& cost,
                      const LocalizeOptions& options, bool mirror, SoftGate* soft) {
  result.reads_used = prep.usable_reads;
  result.segments = static_cast<int>(prep.segments.size());
  if (!result.ok) return;
  result.rms_residual_m = std::sqrt(cost.ssr(result.position) / std::max(1, cost.residual_count()));
  if (auto fail = check_aperture_angle(prep, result.position, options)) {
    fail->reads_used = result.reads_used;
    fail->segments = result.segments;
    result = *fail;
    return;
  }
  // Cycle slips: reads whose unwrapped residual is beyond 0.75π of phase (≥ 4.7σ at σ = 0.5 rad).
  {
    Eigen::VectorXd r;
    cost.evaluate(result.position, r, nullptr);
    int slips = 0, row = 0;
    for (const RangeSegment& s : prep.segments)
      for (size_t k = 0; k < s.range_m.size(); ++k, ++row)
        slips += std::abs(r[row]) * 4.0 * kPi / s.wavelength_m > 0.75 * kPi;
    if (slips > options.max_slip_fraction * r.size()) {
      std::ostringstream why;
      why << slips << " of " << r.size() << " reads are more than 0.75 pi off the fit: cycle slips in the unwrapped phase";
      if (soft) {
        *soft = SoftGate{true, FailReason::kNoisyPhase, why.str()};
      } else {
        result.ok = false;
        result.reason = FailReason::kNoisyPhase;
        result.detail = why.str();
        return;
      }
    }
  }
  const int dof_left = std::max(1, cost.residual_count() - cost.dof() - static_cast<int>(prep.segments.size()));
  gate_uncertainty(result, prep, cost, std::sqrt(cost.ssr(result.position) / dof_left), options, soft);
  if (!result.ok || !mirror) return;
  Objective objective;
  objective.ssr = [&](const Vec3& x) { return cost.ssr(x); };
  objective.refine = [&](const Vec3& x) { return levenberg_marquardt(cost, x, options.lm_max_iterations).position; };
  objective.residuals = cost.residual_count();
  objective.region_min = prep.region_min;
  objective.region_max = prep.region_max;
  // Each segment also costs one offset.
  objective.dof = cost.dof() + static_cast<int>(prep.segments.size());
  const MirrorCheck check = check_mirror(prep.positions, result.position, objective, options, options.noise_floor_m);
  settle_mirror(result, check, prep.positions, prep.orientations, options);
}

}  // namespace rfidray::loc
