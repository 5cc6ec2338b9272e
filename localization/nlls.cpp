// Nonlinear least squares on the unwrapped phase: unknowns tag position (2 or 3) and one phase offset per
// segment, the offsets eliminated in closed form (range_cost.h), solved by Levenberg–Marquardt.
#include <cmath>
#include <limits>
#include <sstream>

#include "localization/finish.h"
#include "localization/grid.h"
#include "localization/joint_fit.h"
#include "localization/methods.h"
#include "localization/range_cost.h"

namespace rfidray::loc {

LocalizeResult localize_nlls(const TagReads& tag, const LocalizeOptions& options, const Vec3* initial) {
  PreparedTag prep;
  if (auto fail = prepare(tag, options, prep)) return *fail;
  RangeCost cost(prep, options.height_known, options.tag_height_m);

  std::vector<Vec3> starts;
  if (initial) {
    starts.push_back(*initial);
    if (options.height_known) starts.back().z() = options.tag_height_m;
  } else {
    // Coarse grid of the same cost (smooth: no wrapping), ≤ 20k points, step ≥ 0.25 m; the 3 best
    // separated minima start LM (one per basin: typically the tag and its mirror).
    const Grid grid = make_grid(prep.region_min, prep.region_max, 0.25, 20000);
    std::vector<double> value(grid.size());
#pragma omp parallel for schedule(static)
    for (long i = 0; i < grid.size(); ++i) value[i] = cost.ssr(grid.point(i));
    for (long i : best_separated(grid, value, 3, 1.0)) starts.push_back(grid.point(i));
  }
  LmResult best;
  best.ssr = std::numeric_limits<double>::infinity();
  int converged = 0;
  for (const Vec3& s : starts) {
    const LmResult r = levenberg_marquardt(cost, s, options.lm_max_iterations);
    if (!r.converged) continue;
    ++converged;
    if (r.ssr < best.ssr) best = r;
  }
  LocalizeResult result;
  result.reads_used = prep.usable_reads;
  if (converged == 0) {
    result = LocalizeResult::failure(FailReason::kNoConvergence,
                                     "Levenberg–Marquardt did not converge within " +
                                         std::to_string(options.lm_max_iterations) + " iterations");
    result.reads_used = prep.usable_reads;
    return result;
  }
  const Vec3 lo = prep.region_min.array() - 1e-9, hi = prep.region_max.array() + 1e-9;
  if ((best.position.array() < lo.array()).any() || (best.position.array() > hi.array()).any()) {
    std::ostringstream why;
    why << "converged outside the search region (farther than " << options.max_range_m << " m from the path)";
    result = LocalizeResult::failure(FailReason::kNoConvergence, why.str());
    result.reads_used = prep.usable_reads;
    return result;
  }
  result.ok = true;
  result.position = best.position;
  // The unwrapped fit's own checks (cycle slips, aperture, predicted σ), then the joint multi-carrier model
  // on the wrapped phases takes over from the unwrapped optimum: final position, honest uncertainty, and the
  // uniqueness test (mirror and the other grid starts as rivals).
  // Its soft gates (cycle slips, predicted σ of the unwrapped fit) leave the position to the joint fit, which
  // does not unwrap: the result is then at best uncertain, with a position and radius.
  SoftGate soft;
  finish_unwrapped(result, prep, cost, options, false, &soft);
  if (!result.ok) return result;
  const JointModel model = make_joint_model(tag, options);
  const Vec3 focused = focus_near(model, result.position, model.min_wavelength_m() / 8.0, options.height_known,
                                    focus_min_step_m(model));
  const JointFit fit = fit_joint(model, focused, options);
  if (auto fail = check_aperture_angle(prep, fit.position, options)) {
    fail->reads_used = result.reads_used;
    return *fail;
  }
  std::vector<Vec3> rivals;
  if (!initial) rivals = starts;
  judge_joint(result, model, fit, rivals, prep, options);
  apply_soft_gate(result, soft);
  return result;
}

}  // namespace rfidray::loc
