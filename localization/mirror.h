#pragma once
// Mirror ambiguity. Phase data constrain only distances to the antenna positions, so they cannot tell a tag
// from its reflection across any plane containing every antenna position:
//  - 2-D (tag height known): a straight horizontal path is symmetric under reflection across the vertical
//    plane through it (z is preserved, so the known height does not help);
//  - 3-D: a planar path is symmetric across its plane, a straight one under any rotation about it.
// Test: reflect the estimate across the best-fit line (2-D) / plane (3-D) of the antenna positions, let the
// method's own objective re-converge from there, and compare fits. If the mirror candidate is distinct and
// fits within `mirror_chi2` χ² units (σ² from the best fit's residual), the data cannot choose: ambiguous.
#include <functional>
#include <vector>

#include "localization/options.h"
#include "localization/result.h"

namespace rfidray::loc {

struct Objective {
  std::function<double(const Vec3&)> ssr;     // sum of squared residuals in the method's units
  std::function<Vec3(const Vec3&)> refine;    // local re-optimisation from a start point
  int residuals = 0;
  int dof = 0;
  Vec3 region_min = Vec3::Constant(-1e300), region_max = Vec3::Constant(1e300);  // admissible candidates
};

struct MirrorCheck {
  bool degenerate = false;  // 3-D with a straight path: a continuum of solutions
  bool ambiguous = false;
  Vec3 mirror = Vec3::Zero();  // re-converged mirror candidate
  double delta_chi2 = 0.0;     // (SSR_mirror − SSR_best) / σ²
};

// Reflection of x across the best-fit line (2-D, horizontal, through the xy of the positions) or the
// best-fit plane (3-D). Returns false when 3-D positions are collinear (no unique plane).
bool reflect_across_path(const std::vector<Vec3>& positions, bool height_known, const Vec3& x, Vec3& out);

MirrorCheck check_mirror(const std::vector<Vec3>& positions, const Vec3& estimate, const Objective& objective,
                         const LocalizeOptions& options, double noise_floor);

// Applies a mirror check to a result: leaves it ok if unambiguous; settles it with the prior when one is
// configured (recording which); otherwise turns it into failed / ambiguous mirror.
void settle_mirror(LocalizeResult& result, const MirrorCheck& check, const std::vector<Vec3>& positions,
                   const std::vector<Quat>& orientations, const LocalizeOptions& options);

}  // namespace rfidray::loc
