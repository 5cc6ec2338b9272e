// libFuzzer harness: the antenna file (io/antenna_file) — what `calibrate` writes and `localize --antenna-file`
// reads. Invariants: tests/fuzz/fuzz_support.h; a file that parses has finite numbers, ascending disjoint allowance
// bands, and writes back to a file that parses to the same text (the writer and the reader agree); the allowance a
// front end takes from it for any tag spacing is a finite number >= 0.
#include <limits>
#include <sstream>
#include <string>

#include "io/antenna_file.h"
#include "localization/localize_request.h"
#include "tests/fuzz/fuzz_support.h"

using namespace rfidray;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  loc::AntennaCalibration c;
  if (!fuzz::run_guarded("fuzz_antenna.yaml", [&] { c = io::parse_antenna_yaml(text, "fuzz_antenna.yaml"); })) return 0;
  fuzz::require_finite(c.phase_centre_offset_m, "phase_centre_offset_m");
  for (double f : c.frequencies_hz)
    if (!(f > 0.0) || !std::isfinite(f)) fuzz::violation("frequency not finite and > 0");
  for (double v : c.carrier_offsets_rad) fuzz::require_finite(v, "carrier_offsets_rad");
  for (double v : c.pattern_rad) fuzz::require_finite(v, "pattern_rad");
  double below = 0.0;
  for (const auto& b : c.allowance_bands) {
    if (b.spacing_from_m < below || !(b.spacing_below_m > b.spacing_from_m)) fuzz::violation("allowance bands not ascending");
    below = b.spacing_below_m;
    fuzz::require_finite(b.base_rad, "band base_rad");
    fuzz::require_finite(b.smooth_factor, "band smooth_factor");
  }
  // Written back, it reads again to the same text.
  std::ostringstream once;
  io::write_antenna_file(once, c);
  loc::AntennaCalibration again;
  if (!fuzz::run_guarded("fuzz_again.yaml", [&] { again = io::parse_antenna_yaml(once.str(), "fuzz_again.yaml"); }))
    fuzz::violation("a parsed antenna file written back does not parse");
  std::ostringstream twice;
  io::write_antenna_file(twice, again);
  if (twice.str() != once.str()) fuzz::violation("an antenna file written back reads to a different file");
  // The front ends' allowance for a few spacings.
  for (double spacing : {0.04, 0.163, 0.2, 10.0}) {
    loc::LocalizeRequest request;
    request.has_antenna_file = true;
    request.tag_spacing_m = spacing;
    loc::LocalizePlan plan = loc::validate(request, loc::LocalizeFieldNames{});
    plan.options.calibration = c;
    loc::apply_calibration_allowance(plan, request);
    fuzz::require_finite(plan.options.systematic_phase_rad, "systematic_phase_rad");
    if (plan.options.systematic_phase_rad < 0.0) fuzz::violation("systematic_phase_rad < 0");
    fuzz::require_finite(plan.options.smooth_misfit_factor, "smooth_misfit_factor");
  }
  return 0;
}
