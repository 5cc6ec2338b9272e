#pragma once
// Module localization — owns tag localization from phase histories: unwrapping, hyperbolic, NLLS, SAR, the
// quality gates and mirror handling. Consumes readings as values (observations.h); includes core/ only.
//
// The three localization methods. Each takes one tag's reads (never the true distance) and returns ok with a
// position, or failed with a reason (localization/result.h).
#include "localization/observations.h"
#include "localization/options.h"
#include "localization/result.h"

namespace rfidray::loc {

// The paper's method (§III-D after Tripicchio et al. 2021): unwrapping + hyperbolic intersection.
LocalizeResult localize_hyperbolic(const TagReads& tag, const LocalizeOptions& options);
// Levenberg–Marquardt on the unwrapped phase (tag position + one offset per segment), started from
// `initial` when given, else from the best point of a coarse grid of the same cost.
LocalizeResult localize_nlls(const TagReads& tag, const LocalizeOptions& options, const Vec3* initial = nullptr);
// Holographic / SAR matched filter on the wrapped phase over a coarse-to-fine grid (no unwrapping).
LocalizeResult localize_sar(const TagReads& tag, const LocalizeOptions& options);

LocalizeResult localize(Method method, const TagReads& tag, const LocalizeOptions& options);

}  // namespace rfidray::loc
