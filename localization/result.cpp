#include "localization/methods.h"

namespace rfidray::loc {

const char* to_string(Method m) {
  switch (m) {
    case Method::kHyperbolic: return "hyperbolic";
    case Method::kNlls: return "nlls";
    case Method::kSar: return "sar";
  }
  return "?";
}

const char* to_string(FailReason r) {
  switch (r) {
    case FailReason::kNone: return "";
    case FailReason::kTooFewReads: return "too few reads";
    case FailReason::kApertureTooShort: return "aperture too short";
    case FailReason::kUndersampled: return "undersampled";
    case FailReason::kNoConvergence: return "no convergence";
    case FailReason::kAmbiguousMirror: return "ambiguous mirror solution";
    case FailReason::kNoisyPhase: return "phase too noisy";
    case FailReason::kInconsistentResiduals: return "residuals inconsistent with the model";
    case FailReason::kAmbiguousPeak: return "ambiguous: another optimum fits as well";
    case FailReason::kBehindAntenna: return "behind the antenna";
    case FailReason::kMultipath: return "multipath from the scene";
    case FailReason::kNotLocated: return "not located: 95% region wider than the search region";
  }
  return "?";
}

const char* to_string(Status s) {
  switch (s) {
    case Status::kOk: return "ok";
    case Status::kUncertain: return "uncertain";
    case Status::kFailed: return "failed";
  }
  return "?";
}

bool parse_method(const std::string& name, Method& out) {
  if (name == "hyperbolic") out = Method::kHyperbolic;
  else if (name == "nlls") out = Method::kNlls;
  else if (name == "sar") out = Method::kSar;
  else return false;
  return true;
}

LocalizeResult localize(Method method, const TagReads& tag, const LocalizeOptions& options) {
  switch (method) {
    case Method::kHyperbolic: return localize_hyperbolic(tag, options);
    case Method::kNlls: return localize_nlls(tag, options);
    case Method::kSar: return localize_sar(tag, options);
  }
  return LocalizeResult::failure(FailReason::kNoConvergence, "unknown method");
}

}  // namespace rfidray::loc
