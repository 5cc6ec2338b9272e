#pragma once
// What every localization method returns: a position with status ok, or failed with a reason — never a
// silent wrong point.
#include <limits>
#include <string>

#include "core/geometry.h"

namespace rfidray::loc {

enum class Method { kHyperbolic, kNlls, kSar };

enum class FailReason {
  kNone,
  kTooFewReads,       // fewer reads than the method needs
  kApertureTooShort,  // antenna path (or its angle seen from the tag) too short to resolve the position
  kUndersampled,      // reads too far apart (> λ/4) to unwrap, or SAR grating lobes
  kNoConvergence,     // optimiser did not converge / no intersection cluster
  kAmbiguousMirror,   // a mirror solution across the (straight/planar) path fits the data as well
  kNoisyPhase,        // cycle slips in the unwrapped phase, or noise too large for the geometry
  kInconsistentResiduals,  // residuals do not fit the model (wrapped-phase σ too large, too many outliers)
  kAmbiguousPeak,     // another optimum (not the mirror) outside the confidence region fits nearly as well
  kBehindAntenna,     // --mirror-prior boresight, yet the best fit lies behind the antenna (prior and data disagree)
  kMultipath,         // the known scene's extra paths bend the phase at the estimate by more than it can be trusted
};

const char* to_string(Method m);
const char* to_string(FailReason r);
// "hyperbolic" | "nlls" | "sar"; returns false for anything else.
bool parse_method(const std::string& name, Method& out);

struct LocalizeResult {
  bool ok = false;
  FailReason reason = FailReason::kNone;
  std::string detail;              // human-readable explanation of the reason
  Vec3 position = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  double rms_residual_m = 0.0;     // RMS of the relative-range residual at the estimate
  double predicted_std_m = 0.0;    // 1-σ position uncertainty from σ̂²(JᵀJ)⁻¹ at the estimate
  // Radius (m) of the 95 % confidence region of `position` in the estimated coordinates (2-D when the
  // height is known, else 3-D), from the actual residuals (joint_fit.h); NaN when failed before a fit.
  double uncertainty_m = std::numeric_limits<double>::quiet_NaN();
  double residual_rad = 0.0;       // robust σ of the wrapped-phase residuals of the joint fit
  // Known-scene allowance at the fit (LocalizeOptions::multipath_phase_rad), rad RMS; NaN when not evaluated.
  double multipath_phase_rad = std::numeric_limits<double>::quiet_NaN();
  int outliers = 0;                // stops trimmed as outliers
  int reads_used = 0;
  int segments = 0;
  std::string mirror_resolved_by;  // non-empty when a detected mirror ambiguity was settled by a prior
  static LocalizeResult failure(FailReason r, std::string detail) {
    LocalizeResult out;
    out.reason = r;
    out.detail = std::move(detail);
    return out;
  }
};

}  // namespace rfidray::loc
