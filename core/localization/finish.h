#pragma once
// Checks shared by the unwrapped-phase methods after they produced an estimate: residual, aperture angle,
// mirror ambiguity (judged on the unwrapped range cost, re-converged by Levenberg–Marquardt).
#include "core/localization/prepare.h"
#include "core/localization/range_cost.h"

namespace rfidray::loc {

void finish_unwrapped(LocalizeResult& result, const PreparedTag& prep, const RangeCost& cost,
                      const LocalizeOptions& options);

}  // namespace rfidray::loc
