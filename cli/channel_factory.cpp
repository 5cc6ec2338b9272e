#include "cli/channel_factory.h"

#include <algorithm>
#include <iostream>

#include "core/error.h"
#include "core/link_sample.h"
#include "raytrace/fidelity.h"
#include "raytrace/raytraced_channel.h"

namespace rfidray::cli {
namespace {

std::shared_ptr<const Scene> scenario_scene(const Scenario& scenario, const std::string& name) {
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
  if (scene->empty() && name != "auto")
    std::cerr << "rfidray: note: channel '" << name << "' with an empty scene is free space\n";
  return scene;
}

}  // namespace

std::vector<std::string> channel_names() { return {"ideal", "los", "los+blocked", "single-bounce", "auto"}; }

TraceOptions trace_options(const ChannelOptionsSpec& spec) {
  TraceOptions o;
  if (spec.candidates) o.candidates = parse_candidate_mode(*spec.candidates, "channel_options.candidates");
  if (spec.candidate_rays) o.candidate_rays = *spec.candidate_rays;
  if (spec.candidate_spread) o.candidate_spread = *spec.candidate_spread;
  if (spec.drop_below_db) o.drop_below_db = *spec.drop_below_db;
  if (spec.max_path_length_m) o.max_path_length_m = *spec.max_path_length_m;
  return o;
}

std::unique_ptr<Channel> make_channel(const std::string& name, const Scenario& scenario, const std::string& field,
                                      std::vector<std::string>* report) {
  if (name == "ideal") return std::make_unique<IdealChannel>();
  if (name == "los" || name == "los+blocked" || name == "single-bounce") {
    TraceOptions options = trace_options(scenario.channel_options);
    options.level = parse_channel_level(name, field);
    return std::make_unique<RaytracedChannel>(scenario_scene(scenario, name), options);
  }
  if (name == "auto") {
    const ChannelOptionsSpec& spec = scenario.channel_options;
    const auto scene = scenario_scene(scenario, name);
    const auto batches = sample_link_batches(scenario, spec.auto_sample_links);
    const FidelityChoice choice = choose_fidelity(
        scene, batches, trace_options(spec), {spec.auto_phase_tolerance_rad, spec.auto_rssi_tolerance_db});
    if (report)
      for (const std::string& line : describe(choice)) report->push_back(line);
    return make_rung_channel(scene, choice.picked);
  }
  std::string known;
  for (const std::string& n : channel_names()) known += (known.empty() ? "" : ", ") + n;
  throw field_error(field, "unknown channel '" + name + "' (known: " + known + ")");
}

}  // namespace rfidray::cli
