#pragma once
// Checks shared by the unwrapped-phase methods after they produced an estimate: residual, aperture angle,
// mirror ambiguity (judged on the unwrapped range cost, re-converged by Levenberg–Marquardt).
#include "localization/prepare.h"
#include "localization/range_cost.h"

namespace rfidray::loc {

// The uncertainty gate: sets predicted_std_m and fails the result when it exceeds options.max_std_m.
// sigma_m: the per-read range noise estimated from the fit.
void gate_uncertainty(LocalizeResult& result, const PreparedTag& prep, const RangeCost& cost, double sigma_m,
                      const LocalizeOptions& options);

// check_mirror = false: the mirror test is left to the caller (the joint-model judgement, joint_fit.h).
void finish_unwrapped(LocalizeResult& result, const PreparedTag& prep, const RangeCost& cost,
                      const LocalizeOptions& options, bool check_mirror = true);

}  // namespace rfidray::loc
