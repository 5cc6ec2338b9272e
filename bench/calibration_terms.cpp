// Which terms of the antenna calibration carry from run to run: `calibrate`'s cross-validation over runs
// (localization/allowance.h, measure_held_out) for the full model and for the model with terms held at 0 —
// the phase pattern, then the phase-centre offset too — so that only the carrier offsets are fitted (the
// nested models `calibrate` itself chooses among, CalibrationOptions::select_terms). Prints, per variant, the
// held-out and in-sample median errors with and without the calibration.
//
//   calibration_terms --pair READINGS.csv,TRUTH.csv [--pair ...] [--height-known] [--folds 5] [--antenna NAME]
#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <iostream>
#include <set>
#include <string>
#include <vector>

#include "io/readings_csv.h"
#include "io/reference_tags.h"
#include "localization/calibration.h"

using namespace rfidray;

int main(int argc, char** argv) {
  CLI::App app{"held-out median errors of the antenna calibration with fewer terms fitted"};
  std::vector<std::string> pairs;
  bool height_known = false;
  int folds = 5;
  std::string antenna_requested;
  app.add_option("--pair", pairs, "READINGS.csv,TRUTH.csv of one run (repeatable)")->required();
  app.add_flag("--height-known", height_known, "antenna and tags in one horizontal plane");
  app.add_option("--folds", folds, "folds of runs")->capture_default_str()->check(CLI::Range(2, 1000));
  app.add_option("--antenna", antenna_requested, "antenna to calibrate (default: the only one)");
  CLI11_PARSE(app, argc, argv);
  try {
    std::vector<loc::CalibrationSample> samples;
    std::set<std::string> antennas;
    int run = 0;
    for (const std::string& pair : pairs) {
      const size_t comma = pair.find(',');
      if (comma == std::string::npos) throw std::invalid_argument("--pair: READINGS.csv,TRUTH.csv, got " + pair);
      const size_t before = samples.size();
      io::add_reference_tags(io::read_readings_csv(pair.substr(0, comma)), io::read_truth_csv(pair.substr(comma + 1)),
                             samples, antennas);
      for (size_t i = before; i < samples.size(); ++i) samples[i].run = run;
      ++run;
    }
    const std::string antenna = io::antenna_to_calibrate(antenna_requested, antennas, "--antenna");
    struct Variant {
      const char* name;
      bool pattern;
      bool offset;
    };
    const Variant variants[] = {{"carriers + offset + pattern (calibrate --all-terms)", true, true},
                                {"carriers + offset", false, true},
                                {"carriers only", false, false}};
    std::printf("%zu runs, %zu reference tags, antenna %s, %d folds\n", pairs.size(), samples.size(), antenna.c_str(),
                folds);
    std::printf("%-42s %28s %28s\n", "terms fitted", "held out: with / without mm", "in-sample: with / without mm");
    for (const Variant& v : variants) {
      loc::CalibrationOptions o;
      o.planar = height_known;
      o.fit_pattern = v.pattern;
      o.fit_offset = v.offset;
      o.select_terms = false;  // each variant as it is (calibrate's own choice among them: select_terms)
      o.held_out_folds = folds;
      const loc::AntennaCalibration c = loc::calibrate_antenna(samples, antenna, o);
      std::printf("%-42s %13.1f / %-12.1f %13.1f / %-12.1f  (offset %.3f %.3f m)\n", v.name,
                  1e3 * c.held_out_median_error_m, 1e3 * c.held_out_median_error_uncalibrated_m,
                  1e3 * c.reference_median_error_m, 1e3 * c.reference_median_error_uncalibrated_m,
                  c.phase_centre_offset_m.x(), c.phase_centre_offset_m.y());
    }
  } catch (const std::exception& e) {
    std::cerr << "calibration_terms: " << e.what() << "\n";
    return 2;
  }
  return 0;
}
