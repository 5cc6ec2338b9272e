#include "adapters/gazebo/rfid_sensors.h"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <set>

#include "io/scenario_yaml.h"
#include "core/error.h"
#include "core/number_text.h"

namespace rfidray::gazebo {
namespace {

const char* const kSeedKeys[] = {"frequency",          "noisephi", "noiserssi", "range", "optional_distribution",
                                 "optional_distribution_params", "communication_gain"};

std::string text_of(const sdf::ElementPtr& e) {
  if (!e->GetValue()) return "";
  std::string s = e->GetValue()->GetAsString();
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.pop_back();
  size_t i = 0;
  while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
  return s.substr(i);
}

// The children of an element as a YAML map {name: value}, each value read as YAML ("eu", "[1, 2]", "{kind: ..}").
YAML::Node children_as_yaml(const sdf::ElementPtr& parent, const std::string& where, const std::set<std::string>* keep,
                            std::vector<std::string>* ignored) {
  YAML::Node map(YAML::NodeType::Map);
  for (sdf::ElementPtr c = parent->GetFirstElement(); c; c = c->GetNextElement()) {
    const std::string key = c->GetName();
    if (keep && !keep->count(key)) {
      if (ignored) ignored->push_back(key);
      continue;
    }
    if (map[key].IsDefined() && !map[key].IsNull())
      throw InputError(where + ": <" + key + "> given twice");
    const std::string text = text_of(c);
    try {
      map[key] = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      throw InputError(where + ": <" + key + ">: malformed value '" + text + "' (" + e.msg + ")");
    }
  }
  return map;
}

// <update_rate> of the sensor (Gazebo's, not a plugin parameter): missing or 0 means every physics step.
void apply_update_rate(const sdf::ElementPtr& sensor, const std::string& where, ReaderParams& r,
                       std::vector<std::string>& notes) {
  const sdf::ElementPtr e = sensor->GetElementImpl("update_rate");
  const std::string text = e ? text_of(e) : "";
  double rate = 0.0;
  if (!text.empty()) {
    char* end = nullptr;
    rate = std::strtod(text.c_str(), &end);
    if (*end != '\0' || !std::isfinite(rate) || rate < 0.0)
      throw InputError(where + ": <update_rate> must be a number >= 0 (got '" + text + "')");
  }
  if (rate > 0.0) {
    r.update_rate_hz = rate;
    return;
  }
  r.update_rate_hz = ReaderParams{}.update_rate_hz;
  notes.push_back(where + ": " + (text.empty() ? "no <update_rate>" : "<update_rate> 0 (every physics step)") +
                  ", reading at " + num(r.update_rate_hz) + " Hz");
}

}  // namespace

ReaderParams seed_default_reader() {
  ReaderParams r;
  r.frequencies_hz = {865.7e6};
  r.phase_offsets_rad = {0.0};
  r.noise_phi_rad = 0.1;
  r.noise_rssi = 0.005;
  r.range_m = 5.0;
  r.communication_gain = 250.0;
  r.optional_distribution = {};
  r.model = ReaderModelKind::kPaper;
  return r;
}

RfidSensorKind rfid_sensor_kind(const sdf::ElementPtr& sensor) {
  const std::string type = sensor->GetAttribute("type") ? sensor->GetAttribute("type")->GetAsString() : "";
  if (type == "rfid") return RfidSensorKind::kAntenna;
  if (type == "rfidtag") return RfidSensorKind::kTag;
  if (type == "custom") {
    if (sensor->GetElementImpl("rfid_antenna")) return RfidSensorKind::kAntenna;
    if (sensor->GetElementImpl("rfid_tag")) return RfidSensorKind::kTag;
  }
  return RfidSensorKind::kNone;
}

ReaderParams antenna_params(const sdf::ElementPtr& sensor, const std::string& where, std::vector<std::string>& notes,
                            std::vector<std::string>& warnings) {
  const std::string type = sensor->GetAttribute("type")->GetAsString();
  ReaderParams r;
  if (type == "rfid") {
    const sdf::ElementPtr plugin = sensor->GetElementImpl("plugin");
    YAML::Node map(YAML::NodeType::Map);
    if (plugin) {
      const std::set<std::string> keep(std::begin(kSeedKeys), std::end(kSeedKeys));
      std::vector<std::string> ignored;
      map = children_as_yaml(plugin, where, &keep, &ignored);
      for (const std::string& k : ignored)
        if (k != "frame") warnings.push_back(where + ": plugin parameter <" + k + "> is not one of the seed plugin's; ignored");
    }
    // The seed plugin ignores the parameters of distribution "none".
    if (map["optional_distribution"].IsScalar() && map["optional_distribution"].Scalar() == "none" &&
        map["optional_distribution_params"].IsDefined() && !map["optional_distribution_params"].IsNull()) {
      notes.push_back(where + ": optional_distribution none: optional_distribution_params ignored (as the seed plugin does)");
      map.remove("optional_distribution_params");
    }
    std::string defaulted;
    const ReaderParams seed = seed_default_reader();
    for (const char* k : kSeedKeys) {
      if (map[k].IsDefined() && !map[k].IsNull()) continue;
      const std::string key = k;
      if (key == "optional_distribution_params") continue;
      std::string value = key == "frequency"            ? num(seed.frequencies_hz[0]) + " Hz"
                          : key == "noisephi"           ? num(seed.noise_phi_rad)
                          : key == "noiserssi"          ? num(seed.noise_rssi)
                          : key == "range"              ? num(seed.range_m) + " m"
                          : key == "communication_gain" ? num(seed.communication_gain)
                                                        : std::string("none");
      defaulted += (defaulted.empty() ? "" : ", ") + key + " " + value;
    }
    if (!defaulted.empty())
      notes.push_back(where + ": " + (plugin ? "" : "no <plugin>; ") + "seed plugin defaults applied: " + defaulted);
    r = io::parse_reader_params(map, where, "plugin", seed);
  } else {
    YAML::Node map = children_as_yaml(sensor->GetElementImpl("rfid_antenna"), where, nullptr, nullptr);
    map.remove("frame");  // antenna_tf_frame's, not a reader parameter
    if (map["update_rate"].IsDefined() || map["update_rate_hz"].IsDefined())
      throw InputError(where + ": <rfid_antenna>: the rate is the sensor's <update_rate>, not an rfid_antenna key");
    r = io::parse_reader_params(map, where, "rfid_antenna", ReaderParams{});
  }
  apply_update_rate(sensor, where, r, notes);
  return r;
}

std::string antenna_tf_frame(const sdf::ElementPtr& sensor) {
  for (const char* holder : {"plugin", "rfid_antenna"})
    if (const sdf::ElementPtr h = sensor->GetElementImpl(holder))
      if (const sdf::ElementPtr f = h->GetElementImpl("frame")) return text_of(f);
  return "";
}

TagParams tag_params(const sdf::ElementPtr& sensor, const std::string& where, std::vector<std::string>& notes,
                     std::vector<std::string>& warnings) {
  (void)notes;
  const sdf::ElementPtr native = sensor->GetElementImpl("rfid_tag");
  if (!native) {
    if (sensor->GetElementImpl("plugin"))
      warnings.push_back(where + ": the seed's rfidtag sensor takes no parameters; <plugin> ignored");
    return TagParams{};
  }
  return io::parse_tag_params(children_as_yaml(native, where, nullptr, nullptr), where, "rfid_tag", TagParams{});
}

}  // namespace rfidray::gazebo
