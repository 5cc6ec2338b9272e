// libFuzzer harness: scenario YAML (io/scenario_yaml). Parses the input as a scenario file; when it parses and
// the run is small (≤ 4 antennas, ≤ 16 tags, ≤ 2 000 reader ticks, no scene meshes), simulates it on the ideal
// channel and checks every reading is finite. Invariants: tests/fuzz/fuzz_support.h.
#include <string>

#include "core/simulation.h"
#include "raytrace/channel_factory.h"
#include "io/scenario_yaml.h"
#include "tests/fuzz/fuzz_support.h"

using namespace rfidray;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string source = (fuzz::scratch_dir() / "fuzz.yaml").string();
  Scenario scenario;
  if (!fuzz::run_guarded("fuzz.yaml", [&] { scenario = io::parse_scenario(text, source); })) return 0;

  for (const AntennaSpec& a : scenario.antennas) {
    for (double f : a.reader.frequencies_hz) fuzz::require_finite(f, "antenna frequency");
    fuzz::require_finite(a.reader.update_rate_hz, "update_rate_hz");
    fuzz::require_finite(a.reader.tx_power_dbm, "tx_power_dbm");
  }
  if (scenario.antennas.size() > 4 || scenario.tags.size() > 16 || !scenario.scene.meshes.empty()) return 0;

  fuzz::run_guarded("fuzz.yaml", [&] {
    const SceneMotion motion = build_motion(scenario);
    const double duration_s = scenario_duration_s(scenario, motion);
    fuzz::require_finite(duration_s, "duration");
    double ticks = 0.0;
    for (const AntennaSpec& a : scenario.antennas) ticks += duration_s * a.reader.update_rate_hz;
    if (!(ticks <= 2000.0)) return;
    const auto channel = make_channel(ChannelLevel::kIdeal, scenario, motion);
    SimulationOptions options;
    options.threads = 1;
    const SimulationResult result = simulate(scenario, motion, *channel, options);
    for (const AntennaResult& antenna : result.antennas)
      for (const ReadRecord& r : antenna.reads) {
        fuzz::require_finite(r.reading.phase_rad, "phase_rad");
        fuzz::require_finite(r.reading.rssi_dbm, "rssi_dbm");
        fuzz::require_finite(r.distance_m, "distance_m");
        fuzz::require_finite(r.antenna_pose.position, "antenna position");
      }
  });
  return 0;
}
