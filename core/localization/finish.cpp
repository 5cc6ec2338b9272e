#include "core/localization/finish.h"

#include <cmath>

#include "core/localization/mirror.h"

namespace rfidray::loc {

void finish_unwrapped(LocalizeResult& result, const PreparedTag& prep, const RangeCost& cost,
                      const LocalizeOptions& options) {
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
