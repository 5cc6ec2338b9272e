#include "cli/channel_factory.h"

#include <algorithm>
#include <iostream>

#include "core/error.h"
#include "raytrace/raytraced_channel.h"

namespace rfidray::cli {

std::vector<std::string> channel_names() { return {"ideal", "los", "los+blocked", "single-bounce"}; }

std::unique_ptr<Channel> make_channel(const std::string& name, const Scenario& scenario, const std::string& field) {
  if (name == "ideal") return std::make_unique<IdealChannel>();
  if (name == "los" || name == "los+blocked" || name == "single-bounce") {
    std::vector<std::string> warnings;
    const auto scene = load_scene(scenario.scene, scenario.source, {}, &warnings);
    // Materials extrapolated below their P.2040 range: once per material and frequency in use.
    std::vector<double> frequencies;
    for (const auto& a : scenario.antennas)
      for (double f : a.reader.frequencies_hz)
        if (std::find(frequencies.begin(), frequencies.end(), f) == frequencies.end()) frequencies.push_back(f);
    std::sort(frequencies.begin(), frequencies.end());
    if (!frequencies.empty())
      for (const auto& w : extrapolation_warnings(*scene, frequencies.front())) warnings.push_back(w);
    for (const auto& w : warnings) std::cerr << "rfidray: warning: " << w << "\n";
    for (const auto& n : scene->notes()) std::cerr << "rfidray: note: " << n << "\n";
    if (scene->empty()) std::cerr << "rfidray: note: channel '" << name << "' with an empty scene is free space\n";
    TraceOptions options;
    options.level = parse_channel_level(name, field);
    return std::make_unique<RaytracedChannel>(scene, options);
  }
  std::string known;
  for (const std::string& n : channel_names()) known += (known.empty() ? "" : ", ") + n;
  throw field_error(field, "unknown channel '" + name + "' (known: " + known + ")");
}

}  // namespace rfidray::cli
