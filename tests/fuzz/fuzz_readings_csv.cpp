// libFuzzer harness: readings CSV (io/readings_csv) — the file `localize` and `compare` read — and its
// grouping into per-tag read sets. Invariants: tests/fuzz/fuzz_support.h; every parsed row and group is finite.
#include <string>
#include <vector>

#include "io/readings_csv.h"
#include "tests/fuzz/fuzz_support.h"

using namespace rfidray;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = fuzz::write_scratch("fuzz_readings.csv", std::string_view(reinterpret_cast<const char*>(data), size));
  std::vector<io::ReadingRow> rows;
  if (!fuzz::run_guarded("fuzz_readings.csv", [&] { rows = io::read_readings_csv(path); })) return 0;
  for (const io::ReadingRow& r : rows) {
    fuzz::require_finite(r.time_s, "time_s");
    fuzz::require_finite(r.antenna_pose.position, "antenna position");
    fuzz::require_finite(r.phase_rad, "phase_rad");
    fuzz::require_finite(r.rssi, "rssi");
    fuzz::require_finite(r.frequency_hz, "frequency_hz");
    fuzz::require_finite(r.distance_m, "distance_m");
  }
  fuzz::run_guarded("fuzz_readings.csv", [&] {
    for (const auto& tag : io::group_by_tag({rows}, 866e6))
      for (const auto& group : tag.groups) {
        fuzz::require_finite(group.frequency_hz, "group frequency_hz");
        if (!(group.frequency_hz > 0.0)) fuzz::violation("group frequency_hz <= 0");
      }
  });
  return 0;
}
