// `rfidray calibrate`: an antenna file (phase centre, carrier offsets, phase pattern) from reference tags at
// known positions (localization/calibration.h, io/antenna_file.h).
#include <CLI/CLI.hpp>
#include <cmath>
#include <fstream>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <set>

#include "cli/json_number.h"
#include "core/error.h"
#include "io/antenna_file.h"
#include "io/atomic_file.h"
#include "io/readings_csv.h"
#include "io/reference_tags.h"
#include "localization/calibration.h"

namespace rfidray::cli {

namespace {

struct CalibrateState {
  std::vector<std::string> pairs;
  std::vector<std::string> allowance_pairs;
  std::string output;
  std::string antenna;
  bool height_known = false;
  bool fold_pi = false;
  bool json = false;
  int held_out_folds = 5;
  bool all_terms = false;
};

nlohmann::json notes(const std::vector<loc::AntennaCalibration::TermNote>& list) {
  nlohmann::json j = nlohmann::json::array();
  for (const auto& n : list) j.push_back({{"term", n.term}, {"why", n.why}});
  return j;
}

// The antenna's own reference tags localized with and without the calibration (antenna_calibration.h).
nlohmann::json references_localized(const loc::AntennaCalibration& c) {
  if (c.reference_error_tags == 0) return nullptr;
  return {{"tags", c.reference_error_tags}, {"median_error_m", c.reference_median_error_m},
          {"median_error_uncalibrated_m", c.reference_median_error_uncalibrated_m},
          {"helps", c.helps_its_references()}};
}

// Each fold of runs localized with the calibration of the other folds and without any (cross-validation over runs),
// with the models tried when the terms were chosen by it (CalibrationOptions::select_terms).
nlohmann::json held_out(const loc::AntennaCalibration& c) {
  if (c.held_out_tags == 0) return nullptr;
  nlohmann::json models = nlohmann::json::array();
  for (const auto& m : c.held_out_models)
    models.push_back({{"terms", m.terms}, {"median_error_m", number_or_null(m.median_error_m)}, {"kept", m.kept}});
  return {{"runs", c.held_out_runs}, {"folds", c.held_out_folds}, {"tags", c.held_out_tags}, {"median_error_m", c.held_out_median_error_m},
          {"median_error_uncalibrated_m", c.held_out_median_error_uncalibrated_m}, {"helps", c.helps_held_out()},
          {"models", models}};
}

void warn_if_no_help(const loc::AntennaCalibration& c) {
  if (!c.helps_held_out())
    std::cerr << "rfidray: warning: calibrate: calibrated on some runs, the antenna localizes the reference tags of "
                 "the other runs worse than without calibration (" << c.held_out_tags << " tags of " << c.held_out_runs
              << " runs in " << c.held_out_folds << " folds: median error " << 1e3 * c.held_out_median_error_m
              << " mm with it, " << 1e3 * c.held_out_median_error_uncalibrated_m
              << " mm without): its terms do not describe what moves these tags' phases, or what they describe "
                 "changed between runs (the reader's carrier offsets, the antenna's mounting, the room); localize "
                 "without --antenna-file, or calibrate from runs of the setup you will localize in\n";
  // Measured on held-out runs, that is the verdict; the in-sample one below is for when it could not be.
  if (c.held_out_tags > 0 || c.helps_its_references()) return;
  std::cerr << "rfidray: warning: calibrate: this calibration does not localize its own " << c.reference_error_tags
            << " reference tags better than none (median error " << 1e3 * c.reference_median_error_m << " mm with it, "
            << 1e3 * c.reference_median_error_uncalibrated_m
            << " mm without): its terms fit the references' phases but not their positions, and tags it was not made "
               "on usually fare worse; compare localize with and without --antenna-file on held-out tags before using "
               "it\n";
}

nlohmann::json allowance(const loc::AntennaCalibration& c) {
  if (!c.has_allowance()) return nullptr;
  nlohmann::json bands = nlohmann::json::array();
  for (const auto& b : c.allowance_bands)
    bands.push_back({{"spacing_from_m", b.spacing_from_m},
                     {"spacing_below_m", number_or_null(b.spacing_below_m)},
                     {"base_rad", b.base_rad}, {"smooth_factor", b.smooth_factor}, {"samples", b.samples},
                     {"coverage", number_or_null(b.coverage)}});
  return {{"base_rad", c.allowance_base_rad}, {"smooth_factor", c.allowance_smooth_factor},
          {"samples", c.allowance_samples}, {"coverage", c.allowance_coverage}, {"bands", bands}};
}

int run_calibrate(const CalibrateState& s) {
  std::vector<loc::CalibrationSample> samples;
  std::set<std::string> antennas;
  int run = 0;  // one per pair (the held-out check leaves one out at a time)
  auto add = [&](const std::string& pair, const char* option, bool fit_geometry) {
    const size_t comma = pair.find(',');
    if (comma == std::string::npos || comma == 0 || comma + 1 == pair.size() || pair.find(',', comma + 1) != std::string::npos)
      throw field_error(option, "must be READINGS.csv,TRUTH.csv (got '" + pair + "')");
    const std::string readings = pair.substr(0, comma), truth_file = pair.substr(comma + 1);
    const size_t before = samples.size();
    io::add_reference_tags(io::read_readings_csv(readings), io::read_truth_csv(truth_file), samples, antennas);
    for (size_t i = before; i < samples.size(); ++i) {
      samples[i].fit_geometry = fit_geometry;
      samples[i].run = run;
    }
    ++run;
  };
  for (const std::string& pair : s.pairs) add(pair, "--pair", true);
  for (const std::string& pair : s.allowance_pairs) add(pair, "--allowance-pair", false);
  const std::string antenna = io::antenna_to_calibrate(s.antenna, antennas, "--antenna");
  loc::CalibrationOptions o;
  o.planar = s.height_known;
  o.fold_pi = s.fold_pi;
  if (s.held_out_folds == 1 || s.held_out_folds < 0)
    throw field_error("--held-out-folds", "must be 0 (no held-out check) or at least 2 (got " +
                                              std::to_string(s.held_out_folds) + ")");
  o.held_out_check = s.held_out_folds >= 2;
  o.held_out_folds = s.held_out_folds;
  o.select_terms = !s.all_terms;
  const loc::AntennaCalibration c = loc::calibrate_antenna(samples, antenna, o);
  io::check_output_path(s.output, "antenna file");
  io::write_file_atomic(s.output, [&](std::ostream& out) { io::write_antenna_file(out, c); }, "antenna file");
  if (s.json) {
    nlohmann::json j{{"antenna", c.antenna},
                     {"output", s.output},
                     {"phase_centre_offset_m", {c.phase_centre_offset_m.x(), c.phase_centre_offset_m.y(), c.phase_centre_offset_m.z()}},
                     {"phase_centre_offset_sd_m", {c.phase_centre_offset_sd_m.x(), c.phase_centre_offset_sd_m.y(), c.phase_centre_offset_sd_m.z()}},
                     {"frequencies_hz", c.frequencies_hz},
                     {"carrier_offsets_rad", c.carrier_offsets_rad},
                     {"carrier_offsets_sd_rad", c.carrier_offsets_sd_rad},
                     {"pattern_rad", c.pattern_rad},
                     {"pattern_sd_rad", c.pattern_sd_rad},
                     {"residual_rms_rad", number_or_null(c.residual_rms_rad)},  // null: nothing fitted
                     {"not_fitted", notes(c.not_fitted)},
                     {"carrier_offsets_not_fitted", c.carriers_not_fitted.empty() ? nlohmann::json(nullptr)
                                                                                 : nlohmann::json(c.carriers_not_fitted)},
                     {"allowance", allowance(c)},
                     {"references_localized", references_localized(c)},
                     {"held_out", held_out(c)},
                     {"prior_bounded", notes(c.prior_bounded)},
                     {"aliased", notes(c.aliased)},
                     {"reads_used", c.reads_used},
                     {"tags_used", c.tags_used}};
    nlohmann::json cov = nlohmann::json::array();
    for (int i = 0; i < loc::kGeometryTerms; ++i) {
      std::vector<double> row(loc::kGeometryTerms);
      for (int k = 0; k < loc::kGeometryTerms; ++k) row[k] = c.geometry_covariance(i, k);
      cov.push_back(row);
    }
    j["geometry_covariance"] = cov;  // rows and columns: dx, dy, dz, az, el, az2, az_el, el2
    std::cout << j.dump(2) << "\n";
  } else {
    std::cout << "antenna " << c.antenna << ": " << c.tags_used << " tag runs, " << c.reads_used
              << " reads, ";
    if (std::isfinite(c.residual_rms_rad))
      std::cout << "residual " << c.residual_rms_rad << " rad RMS; phase centre offset ("
                << c.phase_centre_offset_m.transpose() << ") m; " << c.frequencies_hz.size() << " carriers -> ";
    else
      std::cout << "nothing calibrated (each carrier keeps its own offset; the file holds the radius allowance) -> ";
    std::cout << s.output << "\n";
    if (!c.carriers_not_fitted.empty()) std::cout << "  carrier offsets not fitted: " << c.carriers_not_fitted << "\n";
    for (const auto& n : c.not_fitted) std::cout << "  not fitted (held at 0): " << n.term << ": " << n.why << "\n";
    for (const auto& n : c.prior_bounded) std::cout << "  bounded by the prior: " << n.term << ": " << n.why << "\n";
    for (const auto& n : c.aliased) std::cout << "  aliased: " << n.term << ": " << n.why << "\n";
    if (c.has_allowance())
      std::cout << "  radius allowance (measured on the " << c.allowance_samples << " reference tags, "
                << 100.0 * c.allowance_coverage << " % inside their 95 % radius): max(" << c.allowance_base_rad
                << " rad, " << c.allowance_smooth_factor << " x the fit's smooth misfit)\n";
    for (const auto& b : c.allowance_bands) {
      std::cout << "    on the " << b.samples << " tags " << 100.0 * b.spacing_from_m << " cm";
      if (std::isfinite(b.spacing_below_m)) std::cout << " to " << 100.0 * b.spacing_below_m << " cm";
      else std::cout << " or more";
      std::cout << " from their nearest neighbour (" << 100.0 * b.coverage << " % inside): max(" << b.base_rad << " rad, "
                << b.smooth_factor << " x the smooth misfit); localize --tag-spacing-m uses it\n";
    }
    if (!c.has_allowance())
      std::cout << "  radius allowance: not measured (fewer than 10 reference tags localized)\n";
    if (c.reference_error_tags > 0)
      std::cout << "  its own " << c.reference_error_tags << " reference tags localized (NLLS, side known): median error "
                << 1e3 * c.reference_median_error_m << " mm with this calibration, "
                << 1e3 * c.reference_median_error_uncalibrated_m << " mm without\n";
    if (c.held_out_tags > 0) {
      std::cout << "  held out (" << c.held_out_runs << " runs in " << c.held_out_folds
                << " folds, each fold localized with the calibration of the others, " << c.held_out_tags
                << " tags): median error " << 1e3 * c.held_out_median_error_m << " mm with it, "
                << 1e3 * c.held_out_median_error_uncalibrated_m << " mm without\n";
      for (const auto& m : c.held_out_models) {
        std::cout << "    terms tried: " << m.terms << ": held-out median error ";
        if (std::isfinite(m.median_error_m))
          std::cout << 1e3 * m.median_error_m << " mm";
        else
          std::cout << "not measured";
        std::cout << (m.kept ? " (kept: the lowest, the simpler on a tie)" : "") << "\n";
      }
    } else {
      std::cout << "  held out: not measured (needs reference tags from at least 2 --pair runs, and --held-out-folds not 0)\n";
    }
  }
  warn_if_no_help(c);
  return 0;
}

}  // namespace

std::function<int()> setup_calibrate(CLI::App& app) {
  auto state = std::make_shared<CalibrateState>();
  CLI::App* sub = app.add_subcommand(
      "calibrate",
      "Fit an antenna file (phase-centre offset, per-carrier phase offsets, phase pattern, each with its standard "
      "uncertainty) from readings of reference tags at known positions; use it with `localize --antenna-file`.");
  sub->add_option("--pair", state->pairs, "READINGS.csv,TRUTH.csv of one run (repeatable); truth header name,x,y,z")
      ->required();
  sub->add_option("--allowance-pair", state->allowance_pairs,
                  "READINGS.csv,TRUTH.csv of a run used only to measure the radius allowance, not to fit the antenna "
                  "(repeatable): reference tags of the other setups the antenna will localize in (denser rows, "
                  "other distances)");
  sub->add_option("-o,--output", state->output, "antenna file to write (YAML)")->required();
  sub->add_option("--antenna", state->antenna, "antenna name to calibrate (default: the only one in the readings)");
  sub->add_flag("--height-known", state->height_known,
                "antenna and tags in one horizontal plane: elevation pattern terms and the vertical offset are not "
                "fitted (the data cannot see them). Without it, calibrate finds such terms itself (reference tags and "
                "antenna positions in one plane, or a term the reads do not depend on), holds them at 0 and says so "
                "(not_fitted in the output and the antenna file)");
  sub->add_flag("--fold-pi", state->fold_pi, "the reader reports phase modulo pi: fit twice the phase");
  sub->add_flag("--json", state->json, "print the calibration as JSON");
  sub->add_option("--held-out-folds", state->held_out_folds,
                  "cross-validate over the --pair runs in this many folds: each fold's reference tags localized with "
                  "the calibration of the others and without (0: skip; costs one calibration per fold)")
      ->capture_default_str();
  sub->add_flag("--all-terms", state->all_terms,
                "fit every term the reference geometry determines. Without it, with a held-out check, calibrate also "
                "cross-validates the antenna without its phase pattern, and with carrier offsets only, keeps the model "
                "with the lowest held-out median error (the simpler on a tie) and lists the terms it dropped under "
                "not_fitted with the medians");
  return [state] { return run_calibrate(*state); };
}

}  // namespace rfidray::cli
