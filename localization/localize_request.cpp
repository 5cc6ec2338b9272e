#include "localization/localize_request.h"

#include <cmath>

#include "core/error.h"
#include "core/limits.h"
#include "core/number_text.h"

namespace rfidray::loc {
namespace {

// `!(v > 0)` also rejects NaN (a front end may parse "nan"); inf is no usable value either.
void check_positive(double v, const std::string& field) {
  if (!(v > 0.0) || !std::isfinite(v)) throw field_error(field, "must be a finite number > 0 (got " + num(v) + ")");
}

}  // namespace

LocalizePlan validate(const LocalizeRequest& r, const LocalizeFieldNames& names) {
  LocalizePlan plan;
  if (r.method == "all") {
    plan.methods = {Method::kHyperbolic, Method::kNlls, Method::kSar};
  } else {
    Method m;
    if (!parse_method(r.method, m))
      throw field_error(names.method, "must be hyperbolic, nlls, sar or all (got '" + clip(r.method) + "')");
    plan.methods = {m};
  }
  LocalizeOptions& o = plan.options;
  if (r.mirror_prior == "boresight") o.mirror_prior = MirrorPrior::kBoresight;
  else if (r.mirror_prior == "truth") o.mirror_prior = MirrorPrior::kPoint;
  else if (r.mirror_prior != "none")
    throw field_error(names.mirror_prior, "must be none, boresight or truth (got '" + clip(r.mirror_prior) + "')");
  check_positive(r.frequency_hz, names.frequency_hz);
  check_positive(r.max_range_m, names.max_range_m);
  // A search region wider than the coordinate range is no position at all (and its grids would not fit an int).
  if (r.max_range_m > limits::kMaxCoordinateM)
    throw field_error(names.max_range_m, "must be at most " + num(limits::kMaxCoordinateM) + " m, the coordinate range (got " +
                                             num(r.max_range_m) + ")");
  check_positive(r.stride_m, names.stride_m);
  check_positive(r.max_residual_rad, names.max_residual_rad);
  check_positive(r.max_uncertainty_m, names.max_uncertainty_m);
  const double systematic = r.systematic_phase_rad.value_or(default_systematic_phase_rad(r.has_antenna_file));
  if (!(systematic >= 0.0) || !std::isfinite(systematic))
    throw field_error(names.systematic_phase_rad, "must be a finite number >= 0 (got " + num(systematic) + ")");
  if (r.has_channel && !r.has_scenario) throw field_error(names.channel, "needs " + names.scenario);
  if (r.height_known && !r.has_truth)
    throw field_error(names.height_known, "needs " + names.truth + " (the tag z comes from it)");
  if (o.mirror_prior == MirrorPrior::kPoint && !r.has_truth) throw field_error(names.mirror_prior_truth, "needs " + names.truth);
  if (r.tag_spacing_m) {
    check_positive(*r.tag_spacing_m, names.tag_spacing_m);
    if (!r.has_antenna_file)
      throw field_error(names.tag_spacing_m, "needs " + names.antenna_file + " (it picks that file's allowance for the spacing)");
  }

  o.max_range_m = r.max_range_m;
  o.stride_m = r.stride_m;
  o.fold_pi = r.fold_pi;
  o.max_residual_rad = r.max_residual_rad;
  o.max_uncertainty_m = r.max_uncertainty_m;
  o.systematic_phase_rad = systematic;
  plan.allowance_source = r.systematic_phase_rad ? names.systematic_phase_rad + " (" + num(systematic) + " rad)"
                          : r.has_antenna_file   ? "the default with an antenna file (" + num(systematic) + " rad)"
                                                 : "the default without an antenna file (" + num(systematic) + " rad)";
  o.height_known = r.height_known;
  plan.needs_truth_per_tag = r.height_known || o.mirror_prior == MirrorPrior::kPoint;
  return plan;
}

void apply_calibration_allowance(LocalizePlan& plan, const LocalizeRequest& request) {
  if (request.systematic_phase_rad || !plan.options.calibration) return;
  const AntennaCalibration& c = *plan.options.calibration;
  if (!c.has_allowance()) {
    if (request.tag_spacing_m) plan.allowance_source += "; the antenna file measured no allowance, for any tag spacing";
    return;
  }
  const AntennaCalibration::AllowanceBand* band =
      request.tag_spacing_m ? c.allowance_band_for(*request.tag_spacing_m) : nullptr;
  if (band) {
    plan.options.systematic_phase_rad = band->base_rad;
    plan.options.smooth_misfit_factor = band->smooth_factor;
    const std::string spacing = std::isfinite(band->spacing_below_m)
                                    ? num(band->spacing_from_m) + " to " + num(band->spacing_below_m) + " m"
                                    : num(band->spacing_from_m) + " m or more";
    plan.allowance_source =
        "the antenna file's, measured on " + std::to_string(band->samples) + " reference tags " + spacing + " apart";
    return;
  }
  plan.options.systematic_phase_rad = c.allowance_base_rad;
  plan.options.smooth_misfit_factor = c.allowance_smooth_factor;
  plan.allowance_source = "the antenna file's, measured on all its " + std::to_string(c.allowance_samples) +
                          " reference tags";
  if (request.tag_spacing_m && !c.allowance_bands.empty())
    plan.allowance_source += " (it has none measured on tags " + num(*request.tag_spacing_m) + " m apart)";
  else if (request.tag_spacing_m)
    plan.allowance_source += " (it measured none per tag spacing)";
  else if (!c.allowance_bands.empty())
    plan.allowance_source += " (it has one per tag spacing: give the tags' spacing to use it)";
}

LocalizeOptions tag_options(const LocalizePlan& plan, const std::string& tag, const std::map<std::string, Vec3>& truth,
                            const std::string& truth_source, const LocalizeFieldNames& names,
                            std::function<double(const Vec3& tag_m)> multipath_phase_rad) {
  LocalizeOptions o = plan.options;
  o.multipath_phase_rad = std::move(multipath_phase_rad);
  if (plan.needs_truth_per_tag) {
    const auto t = truth.find(tag);
    if (t == truth.end())
      throw InputError(truth_source + ": no ground truth for tag '" + tag + "' (needed by " + names.height_known +
                       " / " + names.mirror_prior_truth + ")");
    o.tag_height_m = t->second.z();
    o.prior_point = t->second;
  }
  return o;
}

}  // namespace rfidray::loc
