#pragma once
// What every localization method returns. Three outcomes (status()):
//   ok        — a position whose 95 % radius uncertainty_m meets the request (max_uncertainty_m) and every gate;
//   uncertain — a position and its 95 % radius, with the reason it is not ok (radius above the request, a misfit
//               larger than the phase model allows, a short aperture): the answer, but not the accuracy asked for;
//   failed    — no position (too few reads, separated optima a misfitting fit cannot weigh, no convergence, a fit the prior
//               excludes, a 95 % radius wider than the search region), with the reason.
// Never a silent wrong point: an uncertain position is reported with its radius and its reason.
#include <cmath>
#include <limits>
#include <string>

#include "core/geometry.h"

namespace rfidray::loc {

enum class Method { kHyperbolic, kNlls, kSar };

enum class Status { kOk, kUncertain, kFailed };

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
                      // (uncertain when the fit can weigh it: joint_fit.h (b); else failed)
  kBehindAntenna,     // --mirror-prior boresight, yet the best fit lies behind the antenna (prior and data disagree)
  kMultipath,         // the known scene's extra paths bend the phase at the estimate by more than it can be trusted
  kNotLocated,        // the 95 % region is wider than the search region (max_range_m): the reads do not place the tag
};

const char* to_string(Method m);
const char* to_string(FailReason r);
const char* to_string(Status s);  // "ok" | "uncertain" | "failed"
// "hyperbolic" | "nlls" | "sar"; returns false for anything else.
bool parse_method(const std::string& name, Method& out);

struct LocalizeResult {
  bool ok = false;                 // status() == Status::kOk
  FailReason reason = FailReason::kNone;  // why not ok (uncertain or failed)
  std::string detail;              // human-readable explanation of the reason
  Vec3 position = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  double rms_residual_m = 0.0;     // RMS of the relative-range residual at the estimate
  double predicted_std_m = 0.0;    // 1-σ position uncertainty from σ̂²(JᵀJ)⁻¹ at the estimate
  // Radius (m) of the 95 % confidence region of `position` in the estimated coordinates (2-D when the
  // height is known, else 3-D), from the actual residuals (joint_fit.h); NaN when failed before a fit.
  double uncertainty_m = std::numeric_limits<double>::quiet_NaN();
  double residual_rad = 0.0;       // robust σ of the wrapped-phase residuals of the joint fit
  double smooth_residual_rad = 0.0;  // RMS of their smooth part (joint_fit.h)
  // What uncertainty_m is made of (joint_fit.h): statistical radius (noise, jackknife, calibration) + bias bound
  // radius_systematic_rad × radius_bias_m_per_rad (+ the hyperbolic mode's distance to the joint optimum).
  double radius_statistical_m = std::numeric_limits<double>::quiet_NaN();
  double radius_bias_m_per_rad = std::numeric_limits<double>::quiet_NaN();
  double radius_systematic_rad = std::numeric_limits<double>::quiet_NaN();
  // Known-scene allowance at the fit (LocalizeOptions::multipath_phase_rad), rad RMS; NaN when not evaluated.
  double multipath_phase_rad = std::numeric_limits<double>::quiet_NaN();
  int outliers = 0;                // stops trimmed as outliers
  int reads_used = 0;
  int segments = 0;
  std::string mirror_resolved_by;  // non-empty when a detected mirror ambiguity was settled by a prior
  // ok; else uncertain when a position and a finite radius were found; else failed.
  Status status() const {
    if (ok) return Status::kOk;
    return position.allFinite() && std::isfinite(uncertainty_m) ? Status::kUncertain : Status::kFailed;
  }
  bool has_position() const { return status() != Status::kFailed; }
  // Turns the result into failed: no position, no radius (e.g. two optima a misfitting fit cannot weigh).
  void fail_without_position(FailReason r, std::string why) {
    ok = false;
    reason = r;
    detail = std::move(why);
    position = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
    uncertainty_m = std::numeric_limits<double>::quiet_NaN();
  }
  // Keeps position and radius (uncertain when both are finite), with the reason it is not ok.
  void mark_not_ok(FailReason r, std::string why) {
    ok = false;
    reason = r;
    detail = std::move(why);
  }
  static LocalizeResult failure(FailReason r, std::string detail) {
    LocalizeResult out;
    out.reason = r;
    out.detail = std::move(detail);
    return out;
  }
};

}  // namespace rfidray::loc
