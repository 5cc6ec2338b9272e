// libFuzzer harness: real reader logs (io/real_log) — Octane/ItemTest CSV, sllurp JSON/CSV, per-stop files,
// an explicit column map — and their conversion to readings rows with a fixed antenna pose. The first byte
// picks the layout; the rest is the file (for per-stop, the file 0.csv of a directory).
// Invariants: tests/fuzz/fuzz_support.h; phases in [0, 2π), RSSI and frequency finite, frequency > 0.
#include <cmath>
#include <filesystem>
#include <string>

#include "io/real_log.h"
#include "tests/fuzz/fuzz_support.h"

using namespace rfidray;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string_view body(reinterpret_cast<const char*>(data) + 1, size - 1);
  io::RealLogOptions options;
  std::filesystem::path path;
  switch (data[0] % 6) {
    case 0: options.layout = io::LogLayout::kAuto; break;
    case 1: options.layout = io::LogLayout::kOctane; break;
    case 2: options.layout = io::LogLayout::kSllurp; break;
    case 3:
      options.layout = io::LogLayout::kColumns;
      options.columns = io::parse_column_map("epc=EPC,phase=Phase,phase_unit=deg,frequency=Freq,frequency_unit=mhz,"
                                             "rssi=RSSI,time=Time,time_unit=us,antenna=Port");
      break;
    case 4: options.layout = io::LogLayout::kPerStop; break;
    default:
      options.layout = io::LogLayout::kAuto;
      options.channel_plan_hz = io::parse_channel_plan("cn920");
      options.negate_phase = true;
      break;
  }
  if (options.layout == io::LogLayout::kPerStop) {
    std::filesystem::create_directories(fuzz::scratch_dir() / "fuzz_stops");
    path = fuzz::write_scratch("fuzz_stops/0.csv", body).parent_path();
  } else {
    path = fuzz::write_scratch("fuzz_log.csv", body);
  }
  const std::string location = options.layout == io::LogLayout::kPerStop ? "fuzz_stops" : "fuzz_log.csv";
  options.default_frequency_hz = 866.3e6;

  io::RealLog log;
  if (!fuzz::run_guarded(location, [&] { log = io::read_real_log(path, options); })) return 0;
  for (const io::RealRead& r : log.reads) {
    fuzz::require_finite(r.time_s, "time_s");
    fuzz::require_finite(r.rssi_dbm, "rssi_dbm");
    fuzz::require_finite(r.frequency_hz, "frequency_hz");
    if (!(r.frequency_hz > 0.0)) fuzz::violation("frequency_hz <= 0");
    if (!(r.phase_rad >= 0.0 && r.phase_rad < 2.0 * M_PI)) fuzz::violation("phase_rad outside [0, 2π)");
    if (r.position) fuzz::require_finite(*r.position, "read position");
  }
  io::AntennaPoseOptions pose;
  pose.fixed_position = Vec3(0.0, 0.0, 1.0);
  fuzz::run_guarded(location, [&] {
    for (const io::ReadingRow& row : io::to_reading_rows(log, pose)) {
      fuzz::require_finite(row.time_s, "row time_s");
      fuzz::require_finite(row.antenna_pose.position, "row antenna position");
    }
  });
  return 0;
}
