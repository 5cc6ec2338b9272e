// libFuzzer harness: Gazebo SDF world import (adapters/gazebo: sdformat 12 parse, our checks, the radio scene
// built from the world's collisions). Invariants: tests/fuzz/fuzz_support.h; every antenna and tag pose of the
// imported scenario is finite.
#include <string>

#include "adapters/gazebo/gazebo_world.h"
#include "tests/fuzz/fuzz_support.h"

using namespace rfidray;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const auto path = fuzz::write_scratch("fuzz.world", std::string_view(reinterpret_cast<const char*>(data), size));
  io::WorldSourceOptions options;
  options.file = path.string();
  // model:// URIs resolve against the test world's models, so includes and meshes are reached.
  options.resource_path = {RFIDRAY_SOURCE_DIR "/scenes/tests/gazebo/models"};
  io::WorldSource world;
  if (!fuzz::run_guarded("fuzz.world", [&] { world = gazebo::load_world_source(options, "concrete"); })) return 0;
  for (const AntennaSpec& a : world.scenario.antennas) {
    fuzz::require_finite(a.motion.pose.position, "antenna position");
    for (double f : a.reader.frequencies_hz) fuzz::require_finite(f, "antenna frequency");
  }
  for (const TagSpec& t : world.scenario.tags) fuzz::require_finite(t.motion.pose.position, "tag position");
  return 0;
}
