#include "io/scene_multipath.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/units.h"
#include "raytrace/channel_factory.h"
#include "io/scenario_yaml.h"
#include "localization/multipath_allowance.h"

namespace rfidray::io {

SceneMultipath::SceneMultipath(const Scenario& scenario)
    : scenario_(scenario), channel_(make_channel(scenario.channel, scenario)) {}

std::function<double(const Vec3& tag_m)> SceneMultipath::allowance_for(const loc::TagReads& tag) const {
  struct Sample {
    double time_s;
    Endpoint antenna;
    double frequency_hz;
  };
  auto antenna_named = [&](const std::string& name) -> const ReaderParams& {
    for (const AntennaSpec& a : scenario_.antennas)
      if (a.reader.name == name) return a.reader;
    if (scenario_.antennas.size() == 1) return scenario_.antennas.front().reader;
    throw InputError(scenario_.source + ": reads of tag '" + tag.tag + "' name antenna '" + name +
                     "', which this scenario does not have (--scenario must be the scenario of the readings)");
  };
  std::vector<Sample> all;
  for (const loc::ReadGroup& g : tag.groups) {
    const ReaderParams& reader = antenna_named(g.antenna);
    for (const loc::PhaseRead& r : g.reads)
      all.push_back({r.time_s, Endpoint{Pose{r.antenna_m, r.antenna_orientation}, reader.pattern, reader.polarization},
                     g.frequency_hz});
  }
  std::stable_sort(all.begin(), all.end(), [](const Sample& a, const Sample& b) { return a.time_s < b.time_s; });
  std::vector<Sample> samples;
  const size_t n = all.size(), m = std::min<size_t>(n, kSamples);
  for (size_t i = 0; i < m; ++i) samples.push_back(all[m > 1 ? i * (n - 1) / (m - 1) : 0]);

  Endpoint tag_end;
  for (const TagSpec& t : scenario_.tags)
    if (t.tag.name == tag.tag) {
      tag_end = Endpoint{t.motion.pose, t.tag.pattern, t.tag.polarization};
      break;
    }
  std::shared_ptr<const Channel> channel = channel_;
  return [channel, samples = std::move(samples), tag_end](const Vec3& x) {
    std::vector<std::complex<double>> ratio;
    ratio.reserve(samples.size());
    Endpoint t = tag_end;
    t.pose.position = x;
    for (const Sample& s : samples) {
      std::complex<double> h;
      channel->one_way(s.antenna, std::span<const Endpoint>(&t, 1), s.frequency_hz, std::span<std::complex<double>>(&h, 1));
      const double d = (x - s.antenna.pose.position).norm();
      const double k = kTwoPi / wavelength_m(s.frequency_hz);
      // h / h0 with h0 = e^{−jkD}/D.
      ratio.push_back(d > 0.0 ? h * d * std::polar(1.0, k * d) : std::complex<double>(0.0));
    }
    return loc::multipath_phase_rms_rad(ratio);
  };
}

SceneMultipath load_scene_multipath(const std::string& scenario_file, const std::optional<std::string>& channel,
                                    const std::string& channel_field) {
  Scenario scenario = load_scenario(scenario_file);
  if (channel) scenario.channel = parse_channel_level(*channel, channel_field);
  return SceneMultipath(scenario);
}

}  // namespace rfidray::io
