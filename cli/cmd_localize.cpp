// `rfidray localize`: tag positions from readings CSVs with the hyperbolic (paper), NLLS and SAR methods.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <iomanip>
#include <iostream>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>

#include "cli/json_number.h"
#include "io/antenna_file.h"
#include "io/readings_csv.h"
#include "io/scene_multipath.h"
#include "core/error.h"
#include "localization/localize_request.h"
#include "localization/methods.h"
#include "localization/summary.h"

namespace rfidray::cli {

namespace {

struct LocalizeState {
  std::vector<std::string> readings;
  std::string truth, antenna_file, scenario, channel;  // "" = not given
  loc::LocalizeRequest request;  // the options, checked by loc::validate (shared with Python's localize)
  loc::LocalizeFieldNames names;  // of the options below, as CLI11 has them ("--max-range")
  bool json = false;
};


int run_localize(LocalizeState s) {
  s.request.has_truth = !s.truth.empty();
  s.request.has_antenna_file = !s.antenna_file.empty();
  s.request.has_scenario = !s.scenario.empty();
  s.request.has_channel = !s.channel.empty();
  const loc::LocalizeFieldNames& names = s.names;
  loc::LocalizePlan plan = loc::validate(s.request, names);
  const std::vector<loc::Method>& methods = plan.methods;
  if (!s.antenna_file.empty()) plan.options.calibration = io::read_antenna_file(s.antenna_file);
  loc::apply_calibration_allowance(plan, s.request);

  // The known scene: its multipath allowance bounds what a fit cannot see (io/scene_multipath.h).
  std::optional<io::SceneMultipath> scene;
  if (!s.scenario.empty())
    scene = io::load_scene_multipath(s.scenario, s.channel.empty() ? std::nullopt : std::optional(s.channel),
                                     "--channel");

  std::map<std::string, Vec3> truth;
  if (!s.truth.empty()) truth = io::read_truth_csv(s.truth);

  std::vector<std::vector<io::ReadingRow>> files;
  for (const std::string& f : s.readings) files.push_back(io::read_readings_csv(f));
  std::vector<loc::TagReads> tags = io::group_by_tag(files, s.request.frequency_hz);
  io::label_groups_by_antenna(tags);

  nlohmann::json results = nlohmann::json::array();
  // Per method: errors of the ok results (the summary's error columns), and of every result with a position.
  std::map<loc::Method, std::vector<double>> errors, times, positioned_errors, positioned_radii;
  std::map<loc::Method, int> failed, uncertain, outside, positioned_outside;
  for (const loc::TagReads& tag : tags) {
    const loc::LocalizeOptions o =
        loc::tag_options(plan, tag.tag, truth, s.truth, names, scene ? scene->allowance_for(tag) : nullptr);
    const auto t = truth.find(tag.tag);
    for (loc::Method m : methods) {
      const auto start = std::chrono::steady_clock::now();
      const loc::LocalizeResult r = loc::localize(m, tag, o);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      times[m].push_back(ms);
      const loc::Status status = r.status();
      const bool positioned = status != loc::Status::kFailed;
      nlohmann::json j;
      j["name"] = tag.tag;
      j["method"] = loc::to_string(m);
      j["status"] = loc::to_string(status);
      if (!r.ok) {
        j["reason"] = loc::to_string(r.reason);
        j["detail"] = r.detail;
        ++(status == loc::Status::kUncertain ? uncertain : failed)[m];
      }
      j["x"] = positioned ? number_or_null(r.position.x()) : nullptr;
      j["y"] = positioned ? number_or_null(r.position.y()) : nullptr;
      j["z"] = positioned ? number_or_null(r.position.z()) : nullptr;
      if (positioned && t != truth.end()) {
        const double e = (r.position - t->second).norm();
        j["error_m"] = e;
        positioned_errors[m].push_back(e);
        positioned_radii[m].push_back(r.uncertainty_m);
        if (!(e <= r.uncertainty_m)) ++positioned_outside[m];
        if (r.ok) {
          errors[m].push_back(e);
          if (!(e <= r.uncertainty_m)) ++outside[m];
        }
      }
      j["uncertainty_m"] = positioned ? number_or_null(r.uncertainty_m) : nullptr;
      j["residual_rad"] = number_or_null(r.residual_rad);  // robust σ of the wrapped-phase residuals of the fit
      if (positioned)
        j["radius_parts"] = {{"statistical_m", number_or_null(r.radius_statistical_m)},
                             {"bias_m_per_rad", number_or_null(r.radius_bias_m_per_rad)},
                             {"systematic_rad", number_or_null(r.radius_systematic_rad)},
                             {"smooth_residual_rad", number_or_null(r.smooth_residual_rad)}};
      if (scene && !std::isnan(r.multipath_phase_rad)) j["multipath_phase_rad"] = number_or_null(r.multipath_phase_rad);
      if (positioned && !r.mirror_resolved_by.empty()) j["mirror_resolved_by"] = r.mirror_resolved_by;
      j["reads"] = tag.read_count();
      j["time_ms"] = ms;
      results.push_back(j);
    }
  }
  nlohmann::json summary = nlohmann::json::object();
  for (loc::Method m : methods) {
    const loc::ErrorSummary sum = loc::summarize(errors[m], failed[m], times[m]);
    const loc::ErrorSummary all = loc::summarize(positioned_errors[m], failed[m], times[m]);
    const loc::ErrorSummary radius = loc::summarize(positioned_radii[m], failed[m], times[m]);
    summary[loc::to_string(m)] = {{"mean_error_m", number_or_null(sum.mean_error_m)},
                                  {"median_error_m", number_or_null(sum.median_error_m)},
                                  {"max_error_m", number_or_null(sum.max_error_m)},
                                  {"min_error_m", number_or_null(sum.min_error_m)},
                                  {"ok", sum.ok},
                                  {"uncertain", uncertain[m]},
                                  {"failed", sum.failed},
                                  {"ok_outside_uncertainty", outside[m]},
                                  // Every result with a position (ok and uncertain) that has a truth.
                                  {"with_position", {{"count", all.ok},
                                                     {"mean_error_m", number_or_null(all.mean_error_m)},
                                                     {"median_error_m", number_or_null(all.median_error_m)},
                                                     {"max_error_m", number_or_null(all.max_error_m)},
                                                     {"median_uncertainty_m", number_or_null(radius.median_error_m)},
                                                     {"outside_uncertainty", positioned_outside[m]}}},
                                  {"mean_time_ms", number_or_null(sum.mean_time_ms)}};
  }
  if (s.json) {
    // allowance: where the radius's σ_sys came from (the user, the antenna file's band or pooled, the default).
    std::cout << nlohmann::json{{"results", results}, {"summary", summary}, {"allowance", plan.allowance_source}}.dump(2)
              << "\n";
    return 0;
  }
  // The tag column fits the longest name (EPCs are 24 hex digits), so the columns stay aligned.
  size_t tag_width = 16;
  for (const auto& j : results) tag_width = std::max(tag_width, j["name"].get<std::string>().size() + 2);
  const int tag_w = static_cast<int>(tag_width);
  std::cout << std::left << std::setw(tag_w) << "tag" << std::setw(12) << "method" << std::setw(11) << "status"
            << std::right << std::setw(10) << "x" << std::setw(10) << "y" << std::setw(10) << "z" << std::setw(12)
            << "error_mm" << std::setw(10) << "unc_mm" << std::setw(10) << "time_ms" << "  reason\n";
  std::cout << std::fixed;
  for (const auto& j : results) {
    std::cout << std::left << std::setw(tag_w) << j["name"].get<std::string>() << std::setw(12)
              << j["method"].get<std::string>() << std::setw(11) << j["status"].get<std::string>() << std::right
              << std::setprecision(4);
    for (const char* c : {"x", "y", "z"})
      if (j[c].is_null()) std::cout << std::setw(10) << "-";
      else std::cout << std::setw(10) << j[c].get<double>();
    std::cout << std::setprecision(1);
    if (j.contains("error_m")) std::cout << std::setw(12) << 1000.0 * j["error_m"].get<double>();
    else std::cout << std::setw(12) << "-";
    if (j["uncertainty_m"].is_null()) std::cout << std::setw(10) << "-";
    else std::cout << std::setw(10) << 1000.0 * j["uncertainty_m"].get<double>();
    std::cout << std::setw(10) << j["time_ms"].get<double>();
    if (j.contains("reason")) std::cout << "  " << j["reason"].get<std::string>() << ": " << j["detail"].get<std::string>();
    std::cout << "\n";
  }
  std::cout << "\nsummary (errors over ok tags with truth; status uncertain: a position and its radius, not "
               "within --max-uncertainty-m or another gate; failed: no position):\n";
  for (auto& [name, v] : summary.items()) {
    std::cout << "  " << std::left << std::setw(11) << name << std::right << std::setprecision(1);
    for (const char* c : {"mean_error_m", "median_error_m", "max_error_m", "min_error_m"}) {
      std::cout << "  " << c << "=";
      if (v[c].is_null()) std::cout << "-";
      else std::cout << 1000.0 * v[c].get<double>() << "mm";
    }
    std::cout << "  ok=" << v["ok"] << " uncertain=" << v["uncertain"] << " failed=" << v["failed"];
    if (!s.truth.empty()) {
      const auto& w = v["with_position"];
      std::cout << " ok_outside_uncertainty=" << v["ok_outside_uncertainty"] << "\n  " << std::setw(11) << ""
                << "  with a position (ok + uncertain): " << w["count"] << ", median error ";
      if (w["median_error_m"].is_null()) std::cout << "-";
      else std::cout << 1000.0 * w["median_error_m"].get<double>() << "mm";
      std::cout << ", median radius ";
      if (w["median_uncertainty_m"].is_null()) std::cout << "-";
      else std::cout << 1000.0 * w["median_uncertainty_m"].get<double>() << "mm";
      std::cout << ", outside their radius " << w["outside_uncertainty"];
    }
    std::cout << "\n";
  }
  std::cout << "radius allowance: " << plan.allowance_source << "\n";
  return 0;
}

}  // namespace

std::function<int()> setup_localize(CLI::App& app) {
  auto state = std::make_shared<LocalizeState>();
  loc::LocalizeFieldNames& n = state->names;
  CLI::App* sub = app.add_subcommand(
      "localize",
      "Locate tags from readings CSVs (of `rfidray simulate`) with unwrapping + hyperbolic intersection (the "
      "paper's method), Levenberg-Marquardt on the unwrapped phase, or a SAR grid. The CSV's `dist` column is "
      "ground truth and never used.");
  sub->add_option("readings", state->readings,
                  "readings CSV(s): header time,posx,posy,posz,q1,q2,q3,q4,name,dist,phase,rssi[,antenna,channel,"
                  "frequency_hz,...]; one phase history per (file, antenna, channel, frequency)")
      ->required()
      ->check(CLI::ExistingFile);
  n.truth = sub->add_option("--truth", state->truth, "ground truth CSV name,x,y,z: adds error_m and the summary")
      ->check(CLI::ExistingFile)->get_name();
  n.method = sub->add_option("--method", state->request.method, "hyperbolic | nlls | sar | all")->capture_default_str()->get_name();
  n.height_known = sub->add_flag("--height-known", state->request.height_known,
                "2-D localization (the paper's case): each tag's z is taken from --truth and held fixed")->get_name();
  n.mirror_prior = sub->add_option("--mirror-prior", state->request.mirror_prior,
                  "how to settle a detected mirror ambiguity (straight path): none (report failed), boresight "
                  "(the side the antenna +X axis faces), truth (the side of the --truth position: an oracle)")
      ->capture_default_str()->get_name();
  n.antenna_file = sub->add_option("--antenna-file", state->antenna_file,
                  "antenna calibration (YAML, from `rfidray calibrate`): phase centre, carrier offsets and phase "
                  "pattern applied by the joint model of nlls and sar and by the uncertainty of all methods")
      ->check(CLI::ExistingFile)->get_name();
  n.tag_spacing_m = sub->add_option("--tag-spacing-m", state->request.tag_spacing_m,
                  "with --antenna-file: the tags' spacing as laid out (m, each tag to its nearest neighbour); the "
                  "radius then uses the allowance the file measured on reference tags that far apart (denser rows "
                  "need more: their neighbours' coupling), else the one pooled over all its reference tags")
      ->get_name();
  n.scenario = sub->add_option("--scenario", state->scenario,
                  "the scenario the readings come from (or a survey of the site): its scene's extra paths at each "
                  "estimate, over the tag's antenna positions, bound the bias a fit cannot see in its residuals "
                  "(multipath_phase_rad in the JSON; status uncertain, reason multipath, when they make the region "
                  "too large)")
      ->check(CLI::ExistingFile)->get_name();
  n.channel = sub->add_option("--channel", state->channel,
                  "with --scenario: the channel level the readings were simulated with, overrides the scenario's "
                  "`channel` as `simulate --channel` does (ideal, los, los+blocked, single-bounce, double-bounce, "
                  "full-selective, full, auto)")->get_name();
  sub->add_flag("--fold-pi", state->request.fold_pi, "the reader reports phase modulo pi: fit twice the phase");
  n.max_residual_rad = sub->add_option("--max-residual-rad", state->request.max_residual_rad,
                  "status ok needs the robust sigma of the wrapped-phase residuals below this (rad); above it the "
                  "position and radius are still given, status uncertain")
      ->capture_default_str()->get_name();
  n.max_uncertainty_m = sub->add_option("--max-uncertainty-m", state->request.max_uncertainty_m,
                  "status ok needs the 95 % radius uncertainty_m at most this (m): the largest region the "
                  "application accepts; a larger one is still given, status uncertain")
      ->capture_default_str()->get_name();
  n.systematic_phase_rad = sub->add_option(
      "--systematic-phase-rad", state->request.systematic_phase_rad,
      "model-error allowance (rad RMS of an unmodelled smooth phase error) in uncertainty_m; default: the "
      "allowance the antenna file measured on its reference tags (of --tag-spacing-m's band when given and "
      "measured), else 0.1 with --antenna-file, 0.2 without (an uncalibrated antenna's phase "
      "pattern is model error too)")->get_name();
  n.frequency_hz = sub->add_option("--frequency-hz", state->request.frequency_hz, "carrier when the CSV has no frequency column")
      ->capture_default_str()->get_name();
  n.max_range_m = sub->add_option("--max-range", state->request.max_range_m, "search region: within this distance (m) of the path")
      ->capture_default_str()->get_name();
  n.stride_m = sub->add_option("--stride", state->request.stride_m, "hyperbolic: antenna move (m) between conics (minimum)")
      ->capture_default_str()->get_name();
  sub->add_flag("--json", state->json, "print JSON: results[] {name, method, status (ok | uncertain | failed), "
                                       "reason?, x, y, z (null when failed), error_m?, uncertainty_m (95 % radius, "
                                       "null when failed), time_ms}, summary per method (ok, uncertain, failed; "
                                       "with ok_outside_uncertainty and with_position when --truth is given) and "
                                       "allowance (where the radius's model-error allowance came from)");
  n.mirror_prior_truth = n.mirror_prior + " truth";
  return [state] { return run_localize(*state); };
}

}  // namespace rfidray::cli
