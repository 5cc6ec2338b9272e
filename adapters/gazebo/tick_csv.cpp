#include "adapters/gazebo/tick_csv.h"

#include <filesystem>
#include <system_error>

#include "core/error.h"
#include "io/readings_csv.h"

namespace rfidray::gazebo {

TickCsv::TickCsv(const std::string& dir, const Scenario& scenario) {
  if (dir.empty()) return;
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create output directory (" + ec.message() + ")");
  for (const AntennaSpec& a : scenario.antennas) {
    const auto path = std::filesystem::path(dir) / (a.reader.name + ".csv");
    files_.push_back(std::make_unique<std::ofstream>(path, std::ios::binary));
    if (!*files_.back()) throw InputError(path.string() + ": cannot write (check --csv DIR)");
    *files_.back() << io::kReadingsHeader << '\n';
  }
}

void TickCsv::write(const Scenario& scenario, const TickReadings& tick) {
  if (files_.empty()) return;
  io::write_readings_rows(*files_[tick.antenna], scenario, tick.antenna, tick.reads);
  files_[tick.antenna]->flush();
}

}  // namespace rfidray::gazebo
