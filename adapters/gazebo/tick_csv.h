#pragma once
// The live bridges' `--csv DIR`: one readings CSV per antenna (DIR/<antenna>.csv, io/readings_csv.h's
// layout), its header written when opened, each tick's rows appended and flushed at once, so a bridge that
// is stopped leaves every file complete up to its last tick.
//
// Thread safety: none (the bridges write from their one loop). Construction throws InputError naming the
// directory or file that cannot be created; writes do not throw.
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "adapters/gazebo/live_world.h"
#include "core/scenario.h"

namespace rfidray::gazebo {

class TickCsv {
 public:
  // `dir` empty: writes nothing.
  TickCsv(const std::string& dir, const Scenario& scenario);
  void write(const Scenario& scenario, const TickReadings& tick);

 private:
  std::vector<std::unique_ptr<std::ofstream>> files_;  // per antenna; empty without a directory
};

}  // namespace rfidray::gazebo
