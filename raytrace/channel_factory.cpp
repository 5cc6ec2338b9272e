#include "raytrace/channel_factory.h"

#include <algorithm>
#include <iostream>

#include "core/error.h"
#include "core/link_sample.h"
#include "raytrace/fidelity.h"
#include "raytrace/raytraced_channel.h"

namespace rfidray {
namespace {

std::shared_ptr<const Scene> scenario_scene(const Scenario& scenario, ChannelLevel level) {
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
  if (scene->empty() && level != ChannelLevel::kAuto)
    std::cerr << "rfidray: note: channel '" << to_string(level) << "' with an empty scene is free space\n";
  return scene;
}

}  // namespace

std::shared_ptr<const Scene> load_scenario_scene(const Scenario& scenario, ChannelLevel level) {
  return scenario_scene(scenario, level);
}

TraceOptions trace_options(const ChannelOptionsSpec& spec) {
  TraceOptions o;
  if (spec.candidates) o.candidates = parse_candidate_mode(*spec.candidates, "channel_options.candidates");
  if (spec.candidate_rays) o.candidate_rays = *spec.candidate_rays;
  if (spec.candidate_spread) o.candidate_spread = *spec.candidate_spread;
  if (spec.drop_below_db) o.drop_below_db = *spec.drop_below_db;
  if (spec.max_path_length_m) o.max_path_length_m = *spec.max_path_length_m;
  if (spec.thin_post_max_width_m) o.thin_post_max_width_m = *spec.thin_post_max_width_m;
  if (spec.double_diffraction_max_m) o.double_diffraction_max_m = *spec.double_diffraction_max_m;
  return o;
}

std::unique_ptr<Channel> make_channel(ChannelLevel level, const Scenario& scenario, const SceneMotion& motion,
                                      std::vector<std::string>* report) {
  if (level == ChannelLevel::kIdeal) return std::make_unique<IdealChannel>();
  return make_channel(level, scenario, motion, scenario_scene(scenario, level), report);
}

std::unique_ptr<Channel> make_channel(ChannelLevel level, const Scenario& scenario, const SceneMotion& motion,
                                      std::shared_ptr<const Scene> scene, std::vector<std::string>* report) {
  if (level == ChannelLevel::kIdeal) return std::make_unique<IdealChannel>();
  if (level == ChannelLevel::kAuto) {
    const ChannelOptionsSpec& spec = scenario.channel_options;
    const auto batches = sample_link_batches(scenario, motion, spec.auto_sample_links);
    const FidelityChoice choice = choose_fidelity(
        scene, batches, trace_options(spec), {spec.auto_phase_tolerance_rad, spec.auto_rssi_tolerance_db});
    if (report)
      for (const std::string& line : describe(choice)) report->push_back(line);
    return make_rung_channel(std::move(scene), choice.picked);
  }
  return make_channel(level, scenario.channel_options, std::move(scene));
}

std::unique_ptr<Channel> make_channel(ChannelLevel level, const ChannelOptionsSpec& spec,
                                      std::shared_ptr<const Scene> scene) {
  if (level == ChannelLevel::kIdeal) return std::make_unique<IdealChannel>();
  if (level == ChannelLevel::kAuto)
    throw InputError("channel auto: needs a run's motion to sample links; pick a fixed level here");
  TraceOptions options = trace_options(spec);
  options.level = level;
  return std::make_unique<RaytracedChannel>(std::move(scene), options);
}

std::unique_ptr<Channel> make_channel(ChannelLevel level, const Scenario& scenario, std::vector<std::string>* report) {
  if (level == ChannelLevel::kIdeal) return std::make_unique<IdealChannel>();
  return make_channel(level, scenario, build_motion(scenario), report);
}

}  // namespace rfidray
