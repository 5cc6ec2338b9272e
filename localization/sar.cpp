// Holographic / SAR on the joint multi-carrier model (joint_model.h), no unwrapping:
//   S(x) = Σ_g |Σ_{i∈g} w_i exp(j(φ_i − k_g|x − a_i| − pattern_i))| / Σ w  ∈ [0, 1]
// (each offset group summed coherently — its θ_g only rotates the sum — groups added in magnitude).
// Coarse grid (sar_coarse_step_fraction · λ), the best separated peaks zoomed by shrinking 5×5(×5) local grids
// to 1 mm, then LM on the wrapped residuals from the best one (joint_fit.h); the other peaks are the rivals
// of the uniqueness test (grating lobes, multipath peaks).
#include <algorithm>
#include <cmath>
#include <map>
#include <limits>
#include <sstream>
#include <string>

#include "core/units.h"
#include "localization/grid.h"
#include "localization/joint_fit.h"
#include "localization/methods.h"
#include "localization/prepare.h"

namespace rfidray::loc {


LocalizeResult localize_sar(const TagReads& tag, const LocalizeOptions& options) {
  // The shared pre-checks without unwrapping splits (SAR never unwraps).
  LocalizeOptions no_split = options;
  no_split.unwrap.max_step_fraction = std::numeric_limits<double>::infinity();
  no_split.unwrap.max_gap_s = std::numeric_limits<double>::infinity();
  no_split.unwrap.jump_margin_rad = std::numeric_limits<double>::infinity();
  no_split.min_segment_reads = 1;
  no_split.min_segment_extent_m = 0.0;
  PreparedTag prep;
  if (auto fail = prepare(tag, no_split, prep)) return *fail;

  const JointModel model = make_joint_model(tag, options);
  const double lambda_min = model.min_wavelength_m();
  const bool planar = options.height_known;
  const Grid grid = make_grid(prep.region_min, prep.region_max, options.sar_coarse_step_fraction * lambda_min,
                              planar ? 60000 : 120000);
  // The coarse grid (step λ/4) needs no finer aperture sampling than λ/8: reads closer to the last kept one
  // of their group are left out of it (the zoom and the fit use every read).
  TagReads sparse = tag;
  for (ReadGroup& g : sparse.groups) {
    std::vector<PhaseRead> kept;
    for (const PhaseRead& r : g.reads)
      if (kept.empty() || (r.antenna_m - kept.back().antenna_m).norm() >= lambda_min / 8.0) kept.push_back(r);
    g.reads = std::move(kept);
  }
  // Nor does it need every carrier: the carriers are within 0.5 % of each other, so each gives the same
  // peaks and more of them only average the noise. Per antenna the thinned groups with the most reads are
  // kept until they hold kCoarsePointsPerAntenna points (2 of the 8 carriers of a 1 m stage at λ/8); the
  // zoom's second stage and the fit use every carrier.
  constexpr size_t kCoarsePointsPerAntenna = 48;
  {
    std::map<std::string, std::vector<size_t>> by_antenna;
    for (size_t g = 0; g < sparse.groups.size(); ++g) by_antenna[sparse.groups[g].antenna].push_back(g);
    std::vector<bool> keep(sparse.groups.size(), false);
    for (auto& [antenna, groups] : by_antenna) {
      std::stable_sort(groups.begin(), groups.end(), [&](size_t a, size_t b) {
        return sparse.groups[a].reads.size() > sparse.groups[b].reads.size();
      });
      size_t points = 0;
      for (size_t g : groups) {
        if (points >= kCoarsePointsPerAntenna) break;
        keep[g] = true;
        points += sparse.groups[g].reads.size();
      }
    }
    std::vector<ReadGroup> kept;
    for (size_t g = 0; g < sparse.groups.size(); ++g)
      if (keep[g]) kept.push_back(std::move(sparse.groups[g]));
    sparse.groups = std::move(kept);
  }
  const JointModel coarse = make_joint_model(sparse, options);
  std::vector<double> value(grid.size());
#pragma omp parallel for schedule(static)
  for (long i = 0; i < grid.size(); ++i) value[i] = -coarse.coherence(grid.point(i));
  const std::vector<long> peaks = best_separated(grid, value, options.sar_peaks, lambda_min / 2.0);
  if (peaks.empty()) return LocalizeResult::failure(FailReason::kNoConvergence, "empty search grid");
  // Each peak is zoomed on the thinned model (the same aperture and carriers, so the same peak to a fraction
  // of a fringe) and only the best one again on every read; the rivals are re-converged by the uniqueness test.
  std::vector<Vec3> refined;
  std::vector<double> score;
  size_t best = 0;
  for (long i : peaks) {
    refined.push_back(focus_near(coarse, grid.point(i), grid.step_m / 2.0, planar, focus_min_step_m(model)));
    score.push_back(model.coherence(refined.back()));
    if (score.back() > score[best]) best = refined.size() - 1;
  }
  refined[best] = focus_near(model, refined[best], lambda_min / 32.0, planar, focus_min_step_m(model));
  const JointFit fit = fit_joint(model, refined[best], options);
  LocalizeResult result;
  result.reads_used = model.reads();
  result.segments = model.group_count();
  result.ok = true;
  result.position = fit.position;
  result.predicted_std_m = fit.predicted_std_m;
  result.rms_residual_m = fit.residual_rad * lambda_min / (4.0 * kPi);
  if (auto fail = check_aperture_angle(prep, result.position, options)) {
    fail->reads_used = result.reads_used;
    return *fail;
  }
  std::vector<Vec3> rivals;
  for (size_t i = 0; i < refined.size(); ++i)
    if (i != best) rivals.push_back(refined[i]);
  judge_joint(result, model, fit, rivals, prep, options);
  return result;
}

}  // namespace rfidray::loc
