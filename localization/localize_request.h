#pragma once
// One localization request as every front end takes it (`rfidray localize`, Python's rfidray.localize): the
// user's option values, one check of them, and the per-tag LocalizeOptions they give. Front ends read the files
// (readings, truth, antenna file, scenario) themselves; the request only says which of them were given, for the
// checks that tie options to files. Messages name each field as the front end calls it (LocalizeFieldNames), so a
// CLI user reads "--max-range" and a Python user "max_range_m".
// Value types; validate() and tag_options() are pure (thread-safe) and throw InputError only.
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry.h"
#include "localization/options.h"
#include "localization/result.h"

namespace rfidray::loc {

struct LocalizeRequest {
  std::string method = "all";         // hyperbolic | nlls | sar | all
  std::string mirror_prior = "none";  // none | boresight | truth (the side of the truth position: an oracle)
  double frequency_hz = 865.7e6;      // carrier of readings without a frequency column (Hz)
  double max_range_m = LocalizeOptions{}.max_range_m;
  double stride_m = LocalizeOptions{}.stride_m;
  double max_residual_rad = LocalizeOptions{}.max_residual_rad;
  double max_uncertainty_m = LocalizeOptions{}.max_uncertainty_m;
  std::optional<double> systematic_phase_rad;  // empty: default_systematic_phase_rad(has_antenna_file)
  bool height_known = false;                   // 2-D: each tag's z from the truth
  // The tags' spacing (m, each tag's distance to its nearest neighbour, as laid out): picks the antenna file's
  // allowance measured on reference tags of that spacing (AntennaCalibration::allowance_bands); empty: the file's
  // pooled allowance. Needs an antenna file.
  std::optional<double> tag_spacing_m;
  bool fold_pi = false;
  // Which inputs besides the readings were given.
  bool has_truth = false;
  bool has_antenna_file = false;
  bool has_scenario = false;
  bool has_channel = false;  // a channel level for the scenario's multipath allowance (needs the scenario)
};

// The front end's name of each field, as its messages show it.
struct LocalizeFieldNames {
  std::string method, mirror_prior, mirror_prior_truth, frequency_hz, max_range_m, stride_m, max_residual_rad,
      max_uncertainty_m, systematic_phase_rad, height_known, truth, scenario, channel, tag_spacing_m, antenna_file;
};

// A checked request: the methods to run and the options every tag shares.
struct LocalizePlan {
  std::vector<Method> methods;
  LocalizeOptions options;  // calibration left empty: the front end reads the antenna file
  bool needs_truth_per_tag = false;  // height_known or mirror_prior truth: every tag needs its true position
  // Where options.systematic_phase_rad (σ_sys) and smooth_misfit_factor come from, for the user: the user's value,
  // the antenna file's allowance (its band of tag spacing or pooled), or the default. Set by validate and
  // apply_calibration_allowance.
  std::string allowance_source;
};

// Throws InputError "field 'NAME': …" naming the first bad field (NAME from `names`): an unknown method or
// mirror prior, a number that is not finite or out of range (max_range_m at most limits::kMaxCoordinateM), channel without scenario, height_known or
// mirror_prior truth without truth, tag_spacing_m without an antenna file.
LocalizePlan validate(const LocalizeRequest& request, const LocalizeFieldNames& names);

// After the front end read the antenna file into plan.options.calibration: when the user gave no
// systematic_phase_rad and the calibration measured its allowance on its reference tags (allowance.h), that
// allowance (base and smooth-misfit factor) replaces the default — the one measured on reference tags of the
// request's tag_spacing_m when the file has that band, else the pooled one. Says which in plan.allowance_source.
void apply_calibration_allowance(LocalizePlan& plan, const LocalizeRequest& request);

// The options for one tag: the plan's, the tag's true height and prior point when the plan needs them (InputError
// "TRUTH_SOURCE: no ground truth for tag 'NAME' (…)" when `truth` lacks the tag), and the scene's multipath
// allowance for this tag (empty: none).
LocalizeOptions tag_options(const LocalizePlan& plan, const std::string& tag, const std::map<std::string, Vec3>& truth,
                            const std::string& truth_source, const LocalizeFieldNames& names,
                            std::function<double(const Vec3& tag_m)> multipath_phase_rad = {});

}  // namespace rfidray::loc
