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

#include "io/antenna_file.h"
#include "io/readings_csv.h"
#include "io/scene_multipath.h"
#include "core/error.h"
#include "localization/methods.h"
#include "localization/summary.h"

namespace rfidray::cli {

namespace {

struct LocalizeState {
  std::vector<std::string> readings;
  std::string truth;
  std::string method = "all";
  std::string mirror_prior = "none";
  std::string antenna_file;
  std::string scenario;
  std::string channel;
  bool fold_pi = false;
  double max_residual_rad = loc::LocalizeOptions{}.max_residual_rad;
  double max_uncertainty_m = loc::LocalizeOptions{}.max_uncertainty_m;
  // Unset: loc::default_systematic_phase_rad (0.1 rad with an antenna file, 0.2 without).
  double systematic_phase_rad = std::numeric_limits<double>::quiet_NaN();
  bool height_known = false;
  bool json = false;
  bool systematic_phase_rad_given = false;
  double frequency_hz = 865.7e6;
  double max_range_m = 10.0;
  double stride_m = 0.10;
};

nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

int run_localize(const LocalizeState& s) {
  std::vector<loc::Method> methods;
  if (s.method == "all") {
    methods = {loc::Method::kHyperbolic, loc::Method::kNlls, loc::Method::kSar};
  } else {
    loc::Method m;
    if (!loc::parse_method(s.method, m))
      throw field_error("--method", "must be hyperbolic, nlls, sar or all (got '" + s.method + "')");
    methods = {m};
  }
  loc::MirrorPrior prior = loc::MirrorPrior::kNone;
  if (s.mirror_prior == "boresight") prior = loc::MirrorPrior::kBoresight;
  else if (s.mirror_prior == "truth") prior = loc::MirrorPrior::kPoint;
  else if (s.mirror_prior != "none")
    throw field_error("--mirror-prior", "must be none, boresight or truth (got '" + s.mirror_prior + "')");
  // `!(v > 0)` also rejects NaN (CLI11 parses "nan"); inf is no usable value either.
  if (!(s.frequency_hz > 0.0) || !std::isfinite(s.frequency_hz)) throw field_error("--frequency-hz", "must be a finite number > 0");
  if (!(s.max_range_m > 0.0) || !std::isfinite(s.max_range_m)) throw field_error("--max-range", "must be a finite number > 0");
  if (!(s.stride_m > 0.0) || !std::isfinite(s.stride_m)) throw field_error("--stride", "must be a finite number > 0");
  if (!(s.max_residual_rad > 0.0) || !std::isfinite(s.max_residual_rad)) throw field_error("--max-residual-rad", "must be a finite number > 0");
  if (!(s.max_uncertainty_m > 0.0) || !std::isfinite(s.max_uncertainty_m)) throw field_error("--max-uncertainty-m", "must be a finite number > 0");
  if (s.systematic_phase_rad_given &&
      (!(s.systematic_phase_rad >= 0.0) || !std::isfinite(s.systematic_phase_rad)))
    throw field_error("--systematic-phase-rad", "must be a finite number >= 0");
  const double systematic_phase_rad = s.systematic_phase_rad_given
                                          ? s.systematic_phase_rad
                                          : loc::default_systematic_phase_rad(!s.antenna_file.empty());
  std::optional<loc::AntennaCalibration> calibration;
  if (!s.antenna_file.empty()) calibration = io::read_antenna_file(s.antenna_file);

  // The known scene: its multipath allowance bounds what a fit cannot see (io/scene_multipath.h).
  std::optional<io::SceneMultipath> scene;
  if (!s.channel.empty() && s.scenario.empty()) throw field_error("--channel", "needs --scenario");
  if (!s.scenario.empty())
    scene = io::load_scene_multipath(s.scenario, s.channel.empty() ? std::nullopt : std::optional(s.channel),
                                     "--channel");

  std::map<std::string, Vec3> truth;
  if (!s.truth.empty()) truth = io::read_truth_csv(s.truth);
  if (s.height_known && s.truth.empty()) throw field_error("--height-known", "needs --truth (the tag z comes from it)");
  if (prior == loc::MirrorPrior::kPoint && s.truth.empty()) throw field_error("--mirror-prior truth", "needs --truth");

  std::vector<std::vector<io::ReadingRow>> files;
  for (const std::string& f : s.readings) files.push_back(io::read_readings_csv(f));
  std::vector<loc::TagReads> tags = io::group_by_tag(files, s.frequency_hz);
  io::label_groups_by_antenna(tags);

  nlohmann::json results = nlohmann::json::array();
  std::map<loc::Method, std::vector<double>> errors, times;
  std::map<loc::Method, int> failed, outside;
  for (const loc::TagReads& tag : tags) {
    loc::LocalizeOptions o;
    o.max_range_m = s.max_range_m;
    o.stride_m = s.stride_m;
    o.mirror_prior = prior;
    o.calibration = calibration;
    o.fold_pi = s.fold_pi;
    o.max_residual_rad = s.max_residual_rad;
    o.max_uncertainty_m = s.max_uncertainty_m;
    o.systematic_phase_rad = systematic_phase_rad;
    if (scene) o.multipath_phase_rad = scene->allowance_for(tag);
    const auto t = truth.find(tag.tag);
    if (s.height_known || prior == loc::MirrorPrior::kPoint) {
      if (t == truth.end())
        throw InputError(s.truth + ": no ground truth for tag '" + tag.tag + "' (needed by --height-known / --mirror-prior truth)");
      o.height_known = s.height_known;
      o.tag_height_m = t->second.z();
      o.prior_point = t->second;
    }
    for (loc::Method m : methods) {
      const auto start = std::chrono::steady_clock::now();
      const loc::LocalizeResult r = loc::localize(m, tag, o);
      const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      times[m].push_back(ms);
      nlohmann::json j;
      j["name"] = tag.tag;
      j["method"] = loc::to_string(m);
      j["status"] = r.ok ? "ok" : "failed";
      if (!r.ok) {
        j["reason"] = loc::to_string(r.reason);
        j["detail"] = r.detail;
        ++failed[m];
      }
      j["x"] = r.ok ? number_or_null(r.position.x()) : nullptr;
      j["y"] = r.ok ? number_or_null(r.position.y()) : nullptr;
      j["z"] = r.ok ? number_or_null(r.position.z()) : nullptr;
      if (r.ok && t != truth.end()) {
        const double e = (r.position - t->second).norm();
        j["error_m"] = e;
        errors[m].push_back(e);
        if (!(e <= r.uncertainty_m)) ++outside[m];
      }
      j["uncertainty_m"] = r.ok ? number_or_null(r.uncertainty_m) : nullptr;
      j["residual_rad"] = number_or_null(r.residual_rad);  // robust σ of the wrapped-phase residuals of the fit
      if (scene && !std::isnan(r.multipath_phase_rad)) j["multipath_phase_rad"] = number_or_null(r.multipath_phase_rad);
      if (r.ok && !r.mirror_resolved_by.empty()) j["mirror_resolved_by"] = r.mirror_resolved_by;
      j["reads"] = tag.read_count();
      j["time_ms"] = ms;
      results.push_back(j);
    }
  }
  nlohmann::json summary = nlohmann::json::object();
  for (loc::Method m : methods) {
    const loc::ErrorSummary sum = loc::summarize(errors[m], failed[m], times[m]);
    summary[loc::to_string(m)] = {{"mean_error_m", number_or_null(sum.mean_error_m)},
                                  {"median_error_m", number_or_null(sum.median_error_m)},
                                  {"max_error_m", number_or_null(sum.max_error_m)},
                                  {"min_error_m", number_or_null(sum.min_error_m)},
                                  {"ok", sum.ok},
                                  {"failed", sum.failed},
                                  {"ok_outside_uncertainty", outside[m]},
                                  {"mean_time_ms", number_or_null(sum.mean_time_ms)}};
  }
  if (s.json) {
    std::cout << nlohmann::json{{"results", results}, {"summary", summary}}.dump(2) << "\n";
    return 0;
  }
  // The tag column fits the longest name (EPCs are 24 hex digits), so the columns stay aligned.
  size_t tag_width = 16;
  for (const auto& j : results) tag_width = std::max(tag_width, j["name"].get<std::string>().size() + 2);
  const int tag_w = static_cast<int>(tag_width);
  std::cout << std::left << std::setw(tag_w) << "tag" << std::setw(12) << "method" << std::setw(9) << "status"
            << std::right << std::setw(10) << "x" << std::setw(10) << "y" << std::setw(10) << "z" << std::setw(12)
            << "error_mm" << std::setw(10) << "unc_mm" << std::setw(10) << "time_ms" << "  reason\n";
  std::cout << std::fixed;
  for (const auto& j : results) {
    std::cout << std::left << std::setw(tag_w) << j["name"].get<std::string>() << std::setw(12)
              << j["method"].get<std::string>() << std::setw(9) << j["status"].get<std::string>() << std::right
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
  std::cout << "\nsummary (errors over ok tags with truth):\n";
  for (auto& [name, v] : summary.items()) {
    std::cout << "  " << std::left << std::setw(11) << name << std::right << std::setprecision(1);
    for (const char* c : {"mean_error_m", "median_error_m", "max_error_m", "min_error_m"}) {
      std::cout << "  " << c << "=";
      if (v[c].is_null()) std::cout << "-";
      else std::cout << 1000.0 * v[c].get<double>() << "mm";
    }
    std::cout << "  ok=" << v["ok"] << " failed=" << v["failed"];
    if (!s.truth.empty()) std::cout << " ok_outside_uncertainty=" << v["ok_outside_uncertainty"];
    std::cout << "\n";
  }
  return 0;
}

}  // namespace

std::function<int()> setup_localize(CLI::App& app) {
  auto state = std::make_shared<LocalizeState>();
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
  sub->add_option("--truth", state->truth, "ground truth CSV name,x,y,z: adds error_m and the summary")
      ->check(CLI::ExistingFile);
  sub->add_option("--method", state->method, "hyperbolic | nlls | sar | all")->capture_default_str();
  sub->add_flag("--height-known", state->height_known,
                "2-D localization (the paper's case): each tag's z is taken from --truth and held fixed");
  sub->add_option("--mirror-prior", state->mirror_prior,
                  "how to settle a detected mirror ambiguity (straight path): none (report failed), boresight "
                  "(the side the antenna +X axis faces), truth (the side of the --truth position: an oracle)")
      ->capture_default_str();
  sub->add_option("--antenna-file", state->antenna_file,
                  "antenna calibration (YAML, from `rfidray calibrate`): phase centre, carrier offsets and phase "
                  "pattern applied by the joint model of nlls and sar and by the uncertainty of all methods")
      ->check(CLI::ExistingFile);
  sub->add_option("--scenario", state->scenario,
                  "the scenario the readings come from (or a survey of the site): its scene's extra paths at each "
                  "estimate, over the tag's antenna positions, bound the bias a fit cannot see in its residuals "
                  "(multipath_phase_rad in the JSON; status failed, reason multipath, when they make the region "
                  "too large)")
      ->check(CLI::ExistingFile);
  sub->add_option("--channel", state->channel,
                  "with --scenario: the channel level the readings were simulated with, overrides the scenario's "
                  "`channel` as `simulate --channel` does (ideal, los, los+blocked, single-bounce, double-bounce, "
                  "full-selective, full, auto)");
  sub->add_flag("--fold-pi", state->fold_pi, "the reader reports phase modulo pi: fit twice the phase");
  sub->add_option("--max-residual-rad", state->max_residual_rad,
                  "status ok needs the robust sigma of the wrapped-phase residuals below this (rad)")
      ->capture_default_str();
  sub->add_option("--max-uncertainty-m", state->max_uncertainty_m,
                  "status ok needs the 95 % radius uncertainty_m at most this (m): the largest region the "
                  "application accepts")
      ->capture_default_str();
  CLI::Option* systematic = sub->add_option(
      "--systematic-phase-rad", state->systematic_phase_rad,
      "model-error allowance (rad RMS of an unmodelled smooth phase error) in uncertainty_m; default 0.1 with "
      "--antenna-file, 0.2 without (an uncalibrated antenna's phase pattern is model error too)");
  sub->add_option("--frequency-hz", state->frequency_hz, "carrier when the CSV has no frequency column")
      ->capture_default_str();
  sub->add_option("--max-range", state->max_range_m, "search region: within this distance (m) of the path")
      ->capture_default_str();
  sub->add_option("--stride", state->stride_m, "hyperbolic: antenna move (m) between conics (minimum)")
      ->capture_default_str();
  sub->add_flag("--json", state->json, "print JSON: results[] {name, method, status, reason?, x, y, z, error_m?, "
                                       "uncertainty_m (95 % radius, null when failed), time_ms} and summary per "
                                       "method (with ok_outside_uncertainty when --truth is given)");
  return [state, systematic] {
    state->systematic_phase_rad_given = systematic->count() > 0;
    return run_localize(*state);
  };
}

}  // namespace rfidray::cli
