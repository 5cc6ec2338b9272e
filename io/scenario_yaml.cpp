#include "io/scenario_yaml.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <numbers>
#include <set>
#include <sstream>

#include "core/distribution.h"
#include "io/antenna_file.h"
#include "io/checked_yaml.h"
#include "io/tag_antenna_spec.h"
#include "io/tag_generators.h"
#include "core/random.h"
#include "raytrace/scene.h"
#include "core/error.h"
#include "core/gen2_reader.h"
#include "core/reader_model.h"
#include "core/units.h"
#include "core/number_text.h"

namespace rfidray::io {
namespace {


std::string indexed(const std::string& field, size_t i) { return field + "[" + std::to_string(i) + "]"; }

// Names become file names (antennas) or CSV cells (tags): keep them plain.
void check_name(const YamlFile& src, const YAML::Node& n, const std::string& field, const std::string& name,
                bool file_safe) {
  if (name.empty()) throw src.error(n, field, "must not be empty");
  for (char c : name) {
    const bool ok = std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' ||
                    (!file_safe && (c == ':' || c == '/' || c == '#' || c == '+'));
    if (!ok)
      throw src.error(n, field, "'" + clip(name) + "' may only contain letters, digits and _ - ." +
                                    std::string(file_safe ? "" : " : / # +"));
  }
  if (file_safe && (name[0] == '.' || name == "tags" || name == "tags_trajectory"))
    throw src.error(n, field, "'" + clip(name) + "' is reserved or hidden as an output file name");
}

// Orientation keys next to a position: rpy_deg [roll, pitch, yaw] (fixed axes X, Y, Z, applied in that
// order, as in ROS/SDF), yaw_deg, or quaternion [x, y, z, w]. Identity when none is given.
Quat parse_orientation(YamlMap& m) {
  auto f = m.get_one({"rpy_deg", "yaw_deg", "quaternion"});
  if (!f) return Quat::Identity();
  const std::string field = m.field(f->first);
  if (f->first == "yaw_deg")
    return Quat(Eigen::AngleAxisd(m.src().number(f->second, field) * kPi / 180.0, Vec3::UnitZ()));
  if (f->first == "rpy_deg") {
    const Vec3 rpy = m.src().point(f->second, field) * (kPi / 180.0);
    return Quat(Eigen::AngleAxisd(rpy.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Vec3::UnitY()) *
                Eigen::AngleAxisd(rpy.x(), Vec3::UnitX()));
  }
  const std::vector<double> q = m.src().numbers(f->second, field);
  if (q.size() != 4) throw m.src().error(f->second, field, "needs 4 numbers x, y, z, w");
  const Quat quat(q[3], q[0], q[1], q[2]);
  if (quat.norm() < 1e-9) throw m.src().error(f->second, field, "must not be zero");
  return quat.normalized();
}

Pose parse_pose_map(const YamlFile& src, const YAML::Node& n, const std::string& field) {
  YamlMap m(src, n, field);
  Pose p;
  if (auto pos = m.get("position")) p.position = src.point(*pos, m.field("position"));
  p.orientation = parse_orientation(m);
  m.finish();
  return p;
}

AntennaPattern parse_pattern(const YamlFile& src, const YAML::Node& n, const std::string& field, double gain_dbi) {
  AntennaPattern p = isotropic_pattern(gain_dbi);
  if (n.IsScalar()) {
    p.kind = src.located(n, [&] { return parse_pattern_kind(n.Scalar(), field); });
  } else {
    YamlMap m(src, n, field);
    const YAML::Node kind = m.required("kind");
    p.kind = src.located(kind, [&] { return parse_pattern_kind(src.scalar(kind, m.field("kind")), m.field("kind")); });
    p.peak_gain_dbi = m.number("gain_dbi", gain_dbi);
    p.beamwidth_deg = m.non_negative({"beamwidth_deg"}, p.beamwidth_deg);
    p.front_to_back_db = m.number("front_to_back_db", p.front_to_back_db);
    auto az = m.get("azimuth_deg");
    auto el = m.get("elevation_deg");
    auto gains = m.get("gain_table_dbi");
    if (az || el || gains) {
      if (!(az && el && gains))
        throw src.error(n, field, "a table needs azimuth_deg, elevation_deg and gain_table_dbi (one row per elevation)");
      auto table = std::make_shared<PatternTable>();
      table->azimuth_deg = src.numbers(*az, m.field("azimuth_deg"));
      table->elevation_deg = src.numbers(*el, m.field("elevation_deg"));
      if (!gains->IsSequence()) throw src.error(*gains, m.field("gain_table_dbi"), "must be a list of rows");
      for (size_t i = 0; i < gains->size(); ++i) {
        const auto row = src.numbers((*gains)[i], indexed(m.field("gain_table_dbi"), i));
        if (row.size() != table->azimuth_deg.size())
          throw src.error((*gains)[i], indexed(m.field("gain_table_dbi"), i),
                          "needs one gain per azimuth (" + std::to_string(table->azimuth_deg.size()) + ")");
        table->gain_dbi.insert(table->gain_dbi.end(), row.begin(), row.end());
      }
      p.table = table;
    }
    m.finish();
  }
  src.located(n, [&] {
    p.validate(field);
    return 0;
  });
  return p;
}

// An antenna file's calibration (localization/antenna_calibration.h) as reader hardware effects.
void apply_calibration(const YamlFile& src, const YAML::Node& at, const std::string& field,
                       const loc::AntennaCalibration& cal, ReaderParams& r) {
  r.phase_centre_offset_m = cal.phase_centre_offset_m;
  // The calibration's basis is az, el, az², az·el, el² (loc::pattern_basis).
  static_assert(loc::kPatternTerms == 5);
  r.phase_pattern.azimuth_rad = {cal.pattern_rad[0], cal.pattern_rad[2]};
  r.phase_pattern.elevation_rad = {cal.pattern_rad[1], cal.pattern_rad[4]};
  r.phase_pattern.azimuth_elevation_rad = cal.pattern_rad[3];
  r.phase_offsets_rad.assign(r.frequencies_hz.size(), 0.0);
  if (!cal.has_carrier_offsets()) return;
  for (size_t i = 0; i < r.frequencies_hz.size(); ++i) {
    const int c = cal.carrier_index(r.frequencies_hz[i]);
    if (c < 0)
      throw src.error(at, field, "carrier " + num(r.frequencies_hz[i]) + " Hz is not among the calibrated ones");
    r.phase_offsets_rad[i] = cal.carrier_offsets_rad[c];
  }
}

// {azimuth_rad: [a1, a2, ...], elevation_rad: [e1, ...], azimuth_elevation_rad: c} (core/phase_pattern.h)
PhasePattern parse_phase_pattern(const YamlFile& src, const YAML::Node& n, const std::string& field) {
  YamlMap m(src, n, field);
  PhasePattern p;
  if (auto a = m.get("azimuth_rad")) p.azimuth_rad = src.numbers(*a, m.field("azimuth_rad"));
  if (auto e = m.get("elevation_rad")) p.elevation_rad = src.numbers(*e, m.field("elevation_rad"));
  p.azimuth_elevation_rad = m.number("azimuth_elevation_rad", 0.0);
  // The ripple's parameters; parse_scenario draws it once the scenario's seed is known.
  if (m.has("ripple_rms_rad") || m.has("ripple_scale_deg") || m.has("ripple_spread")) {
    p.ripple_rms_rad = m.number("ripple_rms_rad", 0.0);
    const double scale_deg = m.number("ripple_scale_deg", 30.0);
    p.ripple_spread = m.number("ripple_spread", 0.0);
    if (!(p.ripple_spread >= 0.0 && p.ripple_spread <= 2.0))
      throw src.error(*m.get("ripple_spread"), m.field("ripple_spread"), "must be in [0, 2] (log-sd)");
    if (!(p.ripple_rms_rad >= 0.0 && p.ripple_rms_rad <= 3.2))
      throw src.error(*m.get("ripple_rms_rad"), m.field("ripple_rms_rad"), "must be in [0, 3.2] rad");
    if (!(scale_deg >= 1.0 && scale_deg <= 180.0))
      throw src.error(m.has("ripple_scale_deg") ? *m.get("ripple_scale_deg") : n, m.field("ripple_scale_deg"),
                      "must be in [1, 180] degrees");
    p.ripple_scale_rad = scale_deg * std::numbers::pi / 180.0;
  }
  m.finish();
  return p;
}

Polarization parse_polarization(const YamlFile& src, const YAML::Node& n, const std::string& field) {
  Polarization p;
  if (n.IsScalar()) {
    p.kind = src.located(n, [&] { return parse_polarization_kind(n.Scalar(), field); });
    return p;
  }
  YamlMap m(src, n, field);
  const YAML::Node kind = m.required("kind");
  p.kind = src.located(kind, [&] { return parse_polarization_kind(src.scalar(kind, m.field("kind")), m.field("kind")); });
  if (auto axis = m.get("axis")) {
    p.axis_local = src.point(*axis, m.field("axis"));
    if (p.axis_local.norm() < 1e-12) throw src.error(*axis, m.field("axis"), "must not be zero");
  }
  m.finish();
  return p;
}

std::optional<MastParams> parse_mast(YamlMap& m) {
  auto n = m.get("mast");
  if (!n) return std::nullopt;
  YamlMap mast(m.src(), *n, m.field("mast"));
  MastParams p;
  p.z_min_m = m.src().number(mast.required("z_min_m"), mast.field("z_min_m"));
  const YAML::Node zmax = mast.required("z_max_m");
  p.z_max_m = m.src().number(zmax, mast.field("z_max_m"));
  if (p.z_max_m < p.z_min_m)
    throw m.src().error(zmax, mast.field("z_max_m"),
                        "must be >= z_min_m (" + num(p.z_min_m) + ") (got " + num(p.z_max_m) + ")");
  if (!mast.has("speed_m_s")) throw m.src().error(*n, mast.field("speed_m_s"), "is required");
  p.speed_m_s = mast.positive({"speed_m_s"}, 0.0);
  p.start_s = mast.number("start_s", 0.0);
  mast.finish();
  return p;
}

// Where an antenna or tag is and how it moves (see MotionSpec).
MotionSpec parse_motion(YamlMap& m, bool allow_robot, const std::set<std::string>& robot_names) {
  const YamlFile& src = m.src();
  MotionSpec spec;
  m.allow({"position", "waypoints", "speed_m_s", "rpy_deg", "yaw_deg", "quaternion"});
  if (allow_robot) m.allow({"robot", "mount", "mast"});
  const bool has_pos = m.has("position"), has_robot = m.has("robot"), has_wp = m.has("waypoints");
  if (int(has_pos) + int(has_robot) + int(has_wp) > 1)
    throw src.error(m.node(), m.field("position"),
                    "give one of position, robot (with mount), waypoints — not several");
  if (has_robot) {
    const YAML::Node r = *m.get("robot");
    if (!allow_robot) throw src.error(r, m.field("robot"), "tags cannot ride a robot; use waypoints");
    spec.kind = MotionSpec::Kind::kRobot;
    spec.robot = src.scalar(r, m.field("robot"));
    if (!robot_names.count(spec.robot)) {
      std::string known;
      for (const auto& name : robot_names) known += (known.empty() ? "" : ", ") + name;
      throw src.error(r, m.field("robot"),
                      "unknown robot '" + spec.robot + "' (defined: " + (known.empty() ? "none" : known) + ")");
    }
    if (auto mount = m.get("mount")) spec.pose = parse_pose_map(src, *mount, m.field("mount"));
    for (const char* k : {"rpy_deg", "yaw_deg", "quaternion"})
      if (m.has(k)) throw src.error(m.node()[k], m.field(k), "on a robot the orientation goes in mount: {" + std::string(k) + "}");
  } else if (has_wp) {
    const YAML::Node w = *m.get("waypoints");
    spec.kind = MotionSpec::Kind::kWaypoints;
    if (!w.IsSequence() || w.size() == 0) throw src.error(w, m.field("waypoints"), "must be a non-empty list of [x, y, z]");
    for (size_t i = 0; i < w.size(); ++i) spec.waypoints.push_back(src.point(w[i], indexed(m.field("waypoints"), i)));
    if (spec.waypoints.size() > 1 && !m.has("speed_m_s"))
      throw src.error(w, m.field("speed_m_s"), "is required with waypoints");
    spec.speed_m_s = m.positive({"speed_m_s"}, 0.0);
    spec.pose.orientation = parse_orientation(m);
  } else if (has_pos) {
    spec.kind = MotionSpec::Kind::kFixed;
    spec.pose.position = src.point(*m.get("position"), m.field("position"));
    spec.pose.orientation = parse_orientation(m);
  } else {
    throw src.error(m.node(), m.field("position"),
                    allow_robot ? "is required (or robot: NAME with mount:, or waypoints:)"
                                : "is required (or waypoints:)");
  }
  if (spec.kind != MotionSpec::Kind::kRobot && m.has("mount"))
    throw src.error(m.node(), m.field("mount"), "only with robot: NAME");
  if (allow_robot) {
    spec.mast = parse_mast(m);
    if (spec.mast && spec.kind == MotionSpec::Kind::kWaypoints)
      throw src.error(m.node(), m.field("mast"), "a mast needs a fixed position or a robot, not waypoints");
  }
  return spec;
}

RobotSpec parse_robot(const YamlFile& src, const YAML::Node& n, const std::string& field) {
  YamlMap m(src, n, field);
  RobotSpec r;
  r.source_line = src.line(n);
  r.name = m.string("name", "robot");
  check_name(src, n, m.field("name"), r.name, false);
  const YAML::Node w = m.required("waypoints");
  if (!w.IsSequence() || w.size() == 0) throw src.error(w, m.field("waypoints"), "must be a non-empty list of [x, y]");
  for (size_t i = 0; i < w.size(); ++i) r.waypoints.push_back(src.point(w[i], indexed(m.field("waypoints"), i), true));
  DifferentialDriveParams& d = r.drive;
  d.wheel_radius_m = m.positive({"wheel_radius_m"}, d.wheel_radius_m);
  d.track_width_m = m.positive({"track_width_m"}, d.track_width_m);
  // Speeds as body speeds (converted to wheel speeds by eq. 7–8) or as wheel speeds directly.
  auto speed = m.get_one({"speed_m_s", "wheel_speed_rad_s"});
  if (!speed) throw src.error(n, m.field("speed_m_s"), "is required (or wheel_speed_rad_s)");
  const double v = src.number(speed->second, m.field(speed->first));
  if (!(v > 0.0)) throw src.error(speed->second, m.field(speed->first), "must be > 0 (got " + num(v) + ")");
  d.drive_wheel_speed_rad_s = speed->first == "speed_m_s" ? v / d.wheel_radius_m : v;
  auto turn = m.get_one({"turn_rate_rad_s", "turn_wheel_speed_rad_s"});
  if (turn) {
    const double w_turn = src.number(turn->second, m.field(turn->first));
    if (!(w_turn > 0.0)) throw src.error(turn->second, m.field(turn->first), "must be > 0 (got " + num(w_turn) + ")");
    // ω = r (ω_R − ω_L) / d with ω_R = −ω_L (eq. 8).
    d.turn_wheel_speed_rad_s = turn->first == "turn_rate_rad_s" ? w_turn * d.track_width_m / (2.0 * d.wheel_radius_m) : w_turn;
  } else {
    d.turn_wheel_speed_rad_s = 0.5 * d.track_width_m / (2.0 * d.wheel_radius_m);  // default ω = 0.5 rad/s
  }
  if (auto h = m.get("initial_heading_deg")) {
    d.has_initial_heading = true;
    d.initial_heading_rad = src.number(*h, m.field("initial_heading_deg")) * kPi / 180.0;
  }
  d.start_s = m.non_negative({"start_s"}, 0.0);
  m.finish();
  return r;
}

ReaderModelKind parse_model(const YamlFile& src, const YAML::Node& n, const std::string& field) {
  const std::string s = src.scalar(n, field);
  if (s == "paper") return ReaderModelKind::kPaper;
  if (s == "physical") return ReaderModelKind::kPhysical;
  throw src.error(n, field, "unknown reader model '" + clip(s) + "' (paper, physical)");
}

// optional_distribution_params: a list, one number, or the seed plugin's string "a b" / "a, b" / "none".
std::vector<double> parse_params(const YamlFile& src, const YAML::Node& n, const std::string& field) {
  if (n.IsSequence()) return src.numbers(n, field);
  const std::string s = src.scalar(n, field);
  if (s == "none" || s.empty()) return {};
  std::string t = s;
  std::replace(t.begin(), t.end(), ',', ' ');
  std::istringstream in(t);
  std::vector<double> v;
  std::string word;
  while (in >> word) {
    char* end = nullptr;
    const double x = std::strtod(word.c_str(), &end);
    if (end == word.c_str() || *end != '\0' || !std::isfinite(x))
      throw src.error(n, field, "must be numbers (got '" + clip(s) + "')");
    v.push_back(x);
  }
  return v;
}

// The reader keys of an antenna (all but name, start_s and the place) into `r`; absent keys keep r's values.
void parse_reader_keys(YamlMap& m, const YAML::Node& n, ReaderParams& r) {  // n: the map, for messages
  const YamlFile& src = m.src();
  if (m.has("model")) r.model = parse_model(src, *m.get("model"), m.field("model"));

  // Frequencies: one fixed channel, a hopping list, or a named channel plan.
  auto freq = m.get_one({"frequency", "frequency_hz", "frequencies_hz", "hopping"});
  if (freq) {
    const std::string f = m.field(freq->first);
    if (freq->first == "frequencies_hz") {
      r.frequencies_hz = src.numbers(freq->second, f);
      if (r.frequencies_hz.empty()) throw src.error(freq->second, f, "needs at least one frequency");
    } else if (freq->first == "hopping") {
      const std::string plan = src.scalar(freq->second, f);
      if (plan != "eu") throw src.error(freq->second, f, "unknown channel plan '" + clip(plan) + "' (eu)");
      r.frequencies_hz = eu_channels_hz();
    } else {
      r.frequencies_hz = {src.number(freq->second, f)};
    }
    for (size_t i = 0; i < r.frequencies_hz.size(); ++i)
      if (!(r.frequencies_hz[i] > 0.0))
        throw src.error(freq->second, r.frequencies_hz.size() > 1 ? indexed(f, i) : f,
                        "must be > 0 (got " + num(r.frequencies_hz[i]) + ")");
  }
  r.phase_offsets_rad.assign(r.frequencies_hz.size(), 0.0);
  if (auto off = m.get_one({"phase_offset_rad", "phase_offsets_rad"})) {
    const std::string f = m.field(off->first);
    if (off->first == "phase_offset_rad") {
      r.phase_offsets_rad.assign(r.frequencies_hz.size(), src.number(off->second, f));
    } else {
      r.phase_offsets_rad = src.numbers(off->second, f);
      // Checked here, where the line of the list is known; validate() repeats it for readers built in code.
      if (r.phase_offsets_rad.size() != r.frequencies_hz.size())
        throw src.error(off->second, f, "needs one φ0 per channel (" + std::to_string(r.frequencies_hz.size()) +
                                            " frequencies, got " + std::to_string(r.phase_offsets_rad.size()) + ")");
    }
  }
  r.hop_dwell_s = m.positive({"hop_dwell_s"}, r.hop_dwell_s);
  r.tx_power_dbm = m.number("tx_power_dbm", r.tx_power_dbm);
  r.noise_phi_rad = m.non_negative({"noisephi", "noise_phi_rad"}, r.noise_phi_rad);
  r.noise_rssi = m.non_negative({"noiserssi", "noise_rssi"}, r.noise_rssi);
  r.noise_rssi_db = m.non_negative({"noise_rssi_db"}, r.noise_rssi_db);
  r.range_m = m.positive({"range", "range_m"}, r.range_m);
  r.range_sigma = m.non_negative({"range_sigma"}, r.range_sigma);
  {
    auto dist = m.get("optional_distribution");
    auto params = m.get("optional_distribution_params");
    if (dist || params) {
      const std::string name = dist ? src.scalar(*dist, m.field("optional_distribution")) : "";
      const std::vector<double> p =
          params ? parse_params(src, *params, m.field("optional_distribution_params")) : std::vector<double>{};
      // parse_distribution names optional_distribution (unknown name) or optional_distribution_params (bad values).
      try {
        r.optional_distribution = parse_distribution(name, p, m.field("optional_distribution"));
      } catch (const InputError& e) {
        const std::string msg = e.what();
        const bool about_params = params && msg.find("_params") != std::string::npos;
        throw InputError(src.at(about_params ? *params : (dist ? *dist : n)) + msg);
      }
    }
  }
  r.communication_gain = m.positive({"communication_gain"}, r.communication_gain);
  r.update_rate_hz = m.positive({"update_rate", "update_rate_hz"}, r.update_rate_hz);
  if (auto bits = m.get("phase_bits")) {
    const long long b = src.integer(*bits, m.field("phase_bits"));
    if (b < 0 || b > 32) throw src.error(*bits, m.field("phase_bits"), "must be in [0, 32] (got " + std::to_string(b) + ")");
    r.phase_bits = static_cast<int>(b);
  }
  r.rssi_resolution_db = m.non_negative({"rssi_resolution_db"}, r.rssi_resolution_db);
  r.sensitivity_dbm = m.number("sensitivity_dbm", r.sensitivity_dbm);
  r.modulation_factor = m.positive({"modulation_factor"}, r.modulation_factor);
  // An antenna without pattern and gain_dbi keeps the one it has (isotropic 0 dBi by default).
  if (m.has("pattern") || m.has("gain_dbi")) {
    const double gain_dbi = m.number("gain_dbi", 0.0);
    r.pattern = m.has("pattern") ? parse_pattern(src, *m.get("pattern"), m.field("pattern"), gain_dbi)
                                 : isotropic_pattern(gain_dbi);
  }
  if (auto pol = m.get("polarization")) r.polarization = parse_polarization(src, *pol, m.field("polarization"));
  // Hardware effects of real readers (core/reader.h).
  if (auto off = m.get("phase_centre_offset_m")) r.phase_centre_offset_m = src.point(*off, m.field("phase_centre_offset_m"));
  if (auto pp = m.get("phase_pattern")) r.phase_pattern = parse_phase_pattern(src, *pp, m.field("phase_pattern"));
  r.snr_at_sensitivity_db = m.non_negative({"snr_at_sensitivity_db"}, r.snr_at_sensitivity_db);
  if (auto af = m.get("antenna_file")) {
    // A calibrated antenna (rfidray calibrate) is simulated as it was measured: its phase centre, its phase
    // pattern and its carriers' offsets replace the keys that would say the same.
    for (const char* k : {"phase_centre_offset_m", "phase_pattern", "phase_offset_rad", "phase_offsets_rad"})
      if (m.has(k))
        throw src.error(*af, m.field("antenna_file"), std::string("give either antenna_file or ") + k + ", not both");
    std::filesystem::path file = src.scalar(*af, m.field("antenna_file"));
    if (file.is_relative()) file = std::filesystem::path(src.file()).parent_path() / file;
    const loc::AntennaCalibration cal =
        src.located(*af, [&] { return read_antenna_file(file.string()); });
    apply_calibration(src, *af, m.field("antenna_file"), cal, r);
  }
  if (auto rp = m.get("read_probability"))
    r.read_probability = rp->IsSequence() ? src.numbers(*rp, m.field("read_probability"))
                                          : std::vector<double>{src.number(*rp, m.field("read_probability"))};
}


// A reader's `gen2:` block (docs/air-protocol.md): a preset and/or the link keys, the inventory keys, the ports
// (antenna names, resolved by parse_scenario). Range errors name the key's own line.
Gen2ReaderSpec parse_gen2(const YamlFile& src, const YAML::Node& n, const std::string& field) {
  YamlMap m(src, n, field);
  Gen2ReaderSpec g;
  g.source_line = src.line(n);
  std::map<std::string, YAML::Node> nodes;  // key -> node, to locate a range error on its line
  auto take = [&](const char* key) {
    auto v = m.get(key);
    if (v) nodes[key] = *v;
    return v;
  };
  if (auto p = take("preset")) {
    const std::string name = src.scalar(*p, m.field("preset"));
    const auto link = gen2_preset(name);
    if (!link) {
      std::string names;
      for (const std::string& k : gen2_preset_names()) names += (names.empty() ? "" : ", ") + k;
      throw src.error(*p, m.field("preset"), "unknown preset '" + clip(name) + "' (" + names + ")");
    }
    g.preset = name;
    g.link = *link;
  }
  if (auto v = take("tari_us")) g.link.tari_s = src.number(*v, m.field("tari_us")) * 1e-6;
  if (auto v = take("data1_tari")) g.link.data1_tari = src.number(*v, m.field("data1_tari"));
  if (auto v = take("blf_khz")) g.link.blf_hz = src.number(*v, m.field("blf_khz")) * 1e3;
  if (auto v = take("encoding"))
    g.link.encoding = src.located(*v, [&] { return parse_gen2_encoding(src.scalar(*v, m.field("encoding")), m.field("encoding")); });
  if (auto v = take("trext")) g.link.trext = src.boolean(*v, m.field("trext"));
  if (auto v = take("epc_bits")) {
    const long long b = src.integer(*v, m.field("epc_bits"));
    if (b < 16 || b > 496) throw src.error(*v, m.field("epc_bits"), "must be a multiple of 16 in [16, 496] (got " + std::to_string(b) + ")");
    g.link.epc_bits = static_cast<int>(b);
  }
  if (auto v = take("t2_tpri")) g.link.t2_tpri = src.number(*v, m.field("t2_tpri"));
  if (auto v = take("t3_us")) g.link.t3_s = src.number(*v, m.field("t3_us")) * 1e-6;
  if (auto v = take("session")) {
    const long long k = src.integer(*v, m.field("session"));
    if (k < 0 || k > 3) throw src.error(*v, m.field("session"), "must be 0, 1, 2 or 3 (got " + std::to_string(k) + ")");
    g.session = static_cast<int>(k);
  }
  if (auto v = take("target")) {
    const std::string t = src.scalar(*v, m.field("target"));
    if (t == "A") g.target = Gen2Target::kA;
    else if (t == "B") g.target = Gen2Target::kB;
    else if (t == "AB") g.target = Gen2Target::kAB;
    else throw src.error(*v, m.field("target"), "must be A, B or AB (got '" + clip(t) + "')");
  }
  if (auto v = take("q")) {
    const long long q = src.integer(*v, m.field("q"));
    if (q < 0 || q > 15) throw src.error(*v, m.field("q"), "must be in [0, 15] (got " + std::to_string(q) + ")");
    g.q = static_cast<int>(q);
  }
  if (auto v = take("q_algorithm")) {
    const std::string a = src.scalar(*v, m.field("q_algorithm"));
    if (a == "fixed") g.q_mode = Gen2QMode::kFixed;
    else if (a == "adaptive") g.q_mode = Gen2QMode::kAdaptive;
    else throw src.error(*v, m.field("q_algorithm"), "must be fixed or adaptive (got '" + clip(a) + "')");
  }
  if (auto v = take("q_c")) g.q_c = src.number(*v, m.field("q_c"));
  if (auto v = take("select_prefix")) g.select_prefix = src.scalar(*v, m.field("select_prefix"));
  if (auto v = take("capture_db")) g.capture_ratio_db = src.number(*v, m.field("capture_db"));
  if (auto v = take("s1_persistence_s")) g.s1_persistence_s = src.number(*v, m.field("s1_persistence_s"));
  if (auto v = take("s23_persistence_s")) g.s23_persistence_s = src.number(*v, m.field("s23_persistence_s"));
  if (auto v = take("ports")) {
    if (!v->IsSequence() || v->size() == 0) throw src.error(*v, m.field("ports"), "must be a non-empty list of {antenna, dwell_ms}");
    for (size_t i = 0; i < v->size(); ++i) {
      const std::string f = indexed(m.field("ports"), i);
      YamlMap pm(src, (*v)[i], f);
      Gen2Port port;
      port.source_line = src.line((*v)[i]);
      port.antenna_name = src.scalar(pm.required("antenna"), pm.field("antenna"));
      port.dwell_s = pm.non_negative({"dwell_ms"}, 0.0) * 1e-3;
      if (v->size() > 1 && !(port.dwell_s > 0.0))
        throw src.error((*v)[i], pm.field("dwell_ms"), "is required and must be > 0 when the reader has several ports");
      pm.finish();
      g.ports.push_back(port);
    }
  }
  m.finish();
  try {
    // Ports are checked once resolved (parse_scenario); everything else here.
    validate(g, static_cast<size_t>(-1), field);
  } catch (const InputError& e) {
    const std::string msg = e.what();
    for (const auto& [key, node] : nodes)
      if (msg.find("." + key + "'") != std::string::npos) throw InputError(src.at(node) + msg);
    throw InputError(src.at(n) + msg);
  }
  return g;
}

AntennaSpec parse_antenna(const YamlFile& src, const YAML::Node& n, const std::string& field, size_t index,
                          ReaderModelKind default_model, const std::set<std::string>& robots) {
  YamlMap m(src, n, field);
  AntennaSpec a;
  a.source_line = src.line(n);
  ReaderParams& r = a.reader;
  r.name = m.string("name", "antenna" + std::to_string(index));
  check_name(src, m.has("name") ? *m.get("name") : n, m.field("name"), r.name, true);
  r.model = default_model;
  parse_reader_keys(m, n, r);
  if (auto g = m.get("gen2")) a.gen2 = parse_gen2(src, *g, m.field("gen2"));
  a.start_s = m.non_negative({"start_s"}, 0.0);
  a.motion = parse_motion(m, true, robots);
  m.finish();
  src.located(n, [&] {
    validate(r, field);
    return 0;
  });
  return a;
}

// A tag's `antenna:` (docs/tag-antenna.md): a map {type: dipole, length_m, radius_m[, conductivity_s_m]} or
// {type: table, file: F.csv (relative to the scenario file) | rows: [[frequency_hz, resistance_ohm, reactance_ohm],
// ...]}, or the command line's text form (io/tag_antenna_spec.h).
TagAntennaSpec parse_tag_antenna_node(const YamlFile& src, const YAML::Node& n, const std::string& field) {
  if (n.IsScalar()) return src.located(n, [&] { return io::parse_tag_antenna(n.Scalar(), field); });
  YamlMap m(src, n, field);
  TagAntennaSpec a;
  const std::string type = src.scalar(m.required("type"), m.field("type"));
  if (type == "dipole") {
    a.kind = TagAntennaSpec::Kind::kDipole;
    a.dipole.length_m = m.positive({"length_m"}, 0.0);
    a.dipole.radius_m = m.positive({"radius_m"}, 0.0);
    a.dipole.conductivity_s_m = m.non_negative({"conductivity_s_m"}, 0.0);
  } else if (type == "table") {
    a.kind = TagAntennaSpec::Kind::kTable;
    auto src_kind = m.get_one({"file", "rows"});
    if (!src_kind) throw src.error(n, field, "a table needs 'file' (CSV) or 'rows'");
    if (src_kind->first == "file") {
      std::filesystem::path file = src.scalar(src_kind->second, m.field("file"));
      if (file.is_relative()) file = std::filesystem::path(src.file()).parent_path() / file;
      a.table_source = file.string();
      a.table = src.located(src_kind->second, [&] { return io::read_tag_antenna_table(a.table_source); });
    } else {
      const YAML::Node& rows = src_kind->second;
      if (!rows.IsSequence() || rows.size() == 0) throw src.error(rows, m.field("rows"), "must be a list of rows");
      for (size_t i = 0; i < rows.size(); ++i) {
        const auto r = src.numbers(rows[i], indexed(m.field("rows"), i));
        if (r.size() != 3)
          throw src.error(rows[i], indexed(m.field("rows"), i), "needs [frequency_hz, resistance_ohm, reactance_ohm]");
        a.table.push_back({r[0], {r[1], r[2]}});
      }
    }
  } else {
    throw src.error(m.required("type"), m.field("type"), "must be dipole or table (got '" + clip(type) + "')");
  }
  m.finish();
  return a;
}

// A tag's `chip:`: matched (the default) or a map {type: matched, design_frequency_hz} | {type: series|parallel,
// resistance_ohm, capacitance_f}, or the text form.
TagChipSpec parse_tag_chip_node(const YamlFile& src, const YAML::Node& n, const std::string& field) {
  if (n.IsScalar()) return src.located(n, [&] { return io::parse_tag_chip(n.Scalar(), field); });
  YamlMap m(src, n, field);
  TagChipSpec c;
  const std::string type = src.scalar(m.required("type"), m.field("type"));
  if (type == "matched") {
    c.design_frequency_hz = m.non_negative({"design_frequency_hz"}, 0.0);
  } else if (type == "series" || type == "parallel") {
    c.kind = type == "series" ? TagChipSpec::Kind::kSeries : TagChipSpec::Kind::kParallel;
    c.resistance_ohm = m.positive({"resistance_ohm"}, 0.0);
    c.capacitance_f = m.positive({"capacitance_f"}, 0.0);
  } else {
    throw src.error(m.required("type"), m.field("type"), "must be matched, series or parallel (got '" + clip(type) + "')");
  }
  m.finish();
  return c;
}

// A tag's `backing:` (the surface behind it): none | scene | {material: NAME, distance_m: D} |
// {material: dielectric, relative_permittivity: E, conductivity_s_m: S, distance_m: D}, or the text forms
// (io/tag_antenna_spec.h). (`mount:` is a robot mounting pose.)
TagBackingSpec parse_tag_backing_node(const YamlFile& src, const YAML::Node& n, const std::string& field) {
  if (n.IsScalar()) return src.located(n, [&] { return io::parse_tag_backing(n.Scalar(), field); });
  YamlMap m(src, n, field);
  TagBackingSpec mt;
  mt.kind = TagBackingSpec::Kind::kGiven;
  const std::string name = src.scalar(m.required("material"), m.field("material"));
  if (name == "dielectric") {
    const double eps = m.number("relative_permittivity", 0.0), sigma = m.number("conductivity_s_m", 0.0);
    mt.material = src.located(n, [&] { return user_material("dielectric", eps, sigma, 0.0); });
  } else {
    mt.material = src.located(n, [&] { return backing_material(name, field + ".material"); });
  }
  mt.distance_m = m.positive({"distance_m"}, 0.0);
  m.finish();
  return mt;
}

// The radio keys of a tag (gain_dbi, chip_sensitivity_dbm, pattern, polarization, antenna, chip, backing) into `t`.
void parse_tag_keys(YamlMap& m, TagParams& t) {
  const YamlFile& src = m.src();
  t.gain_dbi = m.number("gain_dbi", t.gain_dbi);
  t.chip_sensitivity_dbm = m.number("chip_sensitivity_dbm", t.chip_sensitivity_dbm);
  // The channel takes the tag gain from its pattern: an isotropic one with the tag's gain by default.
  t.pattern = m.has("pattern") ? parse_pattern(src, *m.get("pattern"), m.field("pattern"), t.gain_dbi)
                               : isotropic_pattern(t.gain_dbi);
  if (auto pol = m.get("polarization")) t.polarization = parse_polarization(src, *pol, m.field("polarization"));
  if (auto pp = m.get("phase_pattern")) t.phase_pattern = parse_phase_pattern(src, *pp, m.field("phase_pattern"));
  if (auto a = m.get("antenna")) t.antenna = parse_tag_antenna_node(src, *a, m.field("antenna"));
  if (auto c = m.get("chip")) t.chip = parse_tag_chip_node(src, *c, m.field("chip"));
  if (auto b = m.get("backing")) {
    t.backing = parse_tag_backing_node(src, *b, m.field("backing"));
  } else if (t.antenna.kind != TagAntennaSpec::Kind::kNone) {
    t.backing.kind = TagBackingSpec::Kind::kScene;  // a tag with an antenna is detuned by the scene's metal near it
  }
}

TagSpec parse_tag(const YamlFile& src, const YAML::Node& n, const std::string& field, size_t index) {
  YamlMap m(src, n, field);
  TagSpec t;
  t.source_line = src.line(n);
  t.tag.name = m.string("name", "tag" + std::to_string(index));
  check_name(src, m.has("name") ? *m.get("name") : n, m.field("name"), t.tag.name, false);
  parse_tag_keys(m, t.tag);
  t.start_s = m.non_negative({"start_s"}, 0.0);
  t.motion = parse_motion(m, false, {});
  m.finish();
  src.located(n, [&] {
    validate(t.tag, field);
    return 0;
  });
  return t;
}

// One entry of `tag_sets` (io/tag_generators.h): a name pattern, the tags' radio keys, and a grid or a surface.
TagSetSpec parse_tag_set(const YamlFile& src, const YAML::Node& n, const std::string& field) {
  YamlMap m(src, n, field);
  TagSetSpec t;
  t.field = field;
  t.source_line = src.line(n);
  t.name_pattern = m.string("name", "tag_{i}");
  {
    // The pattern's characters, with the placeholders' braces allowed.
    std::string plain = t.name_pattern;
    for (char& c : plain)
      if (c == '{' || c == '}') c = '_';
    check_name(src, m.has("name") ? *m.get("name") : n, m.field("name"), plain, false);
  }
  parse_tag_keys(m, t.tag);
  t.orientation = parse_orientation(m);
  auto kind = m.get_one({"grid", "surface"});
  if (!kind) throw src.error(n, field, "needs one of 'grid' (a box or plane of tags) and 'surface' (tags on scene surfaces)");
  YamlMap g(src, kind->second, m.field(kind->first));
  if (kind->first == "grid") {
    TagGrid grid;
    grid.min = src.point(g.required("min"), g.field("min"));
    grid.max = src.point(g.required("max"), g.field("max"));
    grid.step_m = g.positive({"step_m"}, 0.0);
    if (!g.has("step_m")) g.required("step_m");
    t.grid = grid;
  } else {
    SurfaceSelection sel;
    sel.material = g.string("material", "");
    sel.mesh = g.string("mesh", "");
    if (auto f = g.get("facing")) sel.facing = src.point(*f, g.field("facing"));
    sel.facing_tolerance_deg = g.non_negative({"facing_tolerance_deg"}, sel.facing_tolerance_deg);
    if (sel.facing_tolerance_deg > 180.0)
      throw src.error(*g.get("facing_tolerance_deg"), g.field("facing_tolerance_deg"), "must be in [0, 180]");
    if (auto w = g.get("within")) {
      YamlMap box(src, *w, g.field("within"));
      const Vec3 lo = src.point(box.required("min"), box.field("min")), hi = src.point(box.required("max"), box.field("max"));
      box.finish();
      if ((hi - lo).minCoeff() < 0.0) throw src.error(*w, g.field("within"), "max must be >= min on every axis");
      sel.within = std::make_pair(lo, hi);
    }
    sel.offset_m = g.number("offset_m", sel.offset_m);
    sel.step_m = g.positive({"step_m"}, sel.step_m);
    t.surface = sel;
  }
  g.finish();
  m.finish();
  src.located(n, [&] {
    validate(t.tag, field);
    return 0;
  });
  return t;
}

SceneSpec parse_scene(const YamlFile& src, const YAML::Node& n, const std::filesystem::path& base_dir) {
  YamlMap m(src, n, "scene");
  SceneSpec s;
  if (auto meshes = m.get("meshes")) {
    if (!meshes->IsSequence()) throw src.error(*meshes, "scene.meshes", "must be a list of {file, material}");
    for (size_t i = 0; i < meshes->size(); ++i) {
      const YAML::Node mn = (*meshes)[i];
      YamlMap mm(src, mn, indexed("scene.meshes", i));
      MeshSpec mesh;
      mesh.source_line = src.line(mn);
      const YAML::Node file = mm.required("file");
      const std::filesystem::path p = src.scalar(file, mm.field("file"));
      mesh.file = (p.is_absolute() ? p : base_dir / p).lexically_normal().string();
      if (!std::filesystem::is_regular_file(mesh.file))
        throw src.error(file, mm.field("file"), (std::filesystem::exists(mesh.file) ? "not a regular file '" : "no such file '") +
                                                    clip(mesh.file, 200) + "'");
      mesh.material = mm.string("material", "");
      if (auto pos = mm.get("position")) mesh.pose.position = src.point(*pos, mm.field("position"));
      mesh.pose.orientation = parse_orientation(mm);
      if (auto sc = mm.get("scale")) {
        mesh.scale = sc->IsSequence() ? src.point(*sc, mm.field("scale"))
                                      : Vec3::Constant(src.number(*sc, mm.field("scale")));
        if ((mesh.scale.array() <= 0.0).any()) throw src.error(*sc, mm.field("scale"), "must be > 0");
      }
      mm.finish();
      s.meshes.push_back(mesh);
    }
  }
  if (auto mats = m.get("materials")) {
    if (!mats->IsSequence()) throw src.error(*mats, "scene.materials", "must be a list");
    for (size_t i = 0; i < mats->size(); ++i) {
      YamlMap mm(src, (*mats)[i], indexed("scene.materials", i));
      MaterialSpec mat;
      mat.source_line = src.line((*mats)[i]);
      mat.name = src.scalar(mm.required("name"), mm.field("name"));
      if (!mm.has("relative_permittivity"))
        throw src.error((*mats)[i], mm.field("relative_permittivity"), "is required");
      mat.relative_permittivity = mm.positive({"relative_permittivity"}, 1.0);
      mat.conductivity_s_m = mm.non_negative({"conductivity_s_m"}, 0.0);
      mat.thickness_m = mm.non_negative({"thickness_m"}, 0.0);
      if (auto v = mm.get("solid")) mat.solid = src.boolean(*v, mm.field("solid"));
      mm.finish();
      s.materials.push_back(mat);
    }
  }
  if (auto map = m.get("material_map")) {
    if (!map->IsMap()) throw src.error(*map, "scene.material_map", "must be a map {mesh material: radio material}");
    for (auto it = map->begin(); it != map->end(); ++it) {
      const std::string from = it->first.Scalar();
      s.material_map.push_back({from, src.scalar(it->second, "scene.material_map." + from)});
    }
  }
  s.default_material = m.string("default_material", "");
  m.finish();
  return s;
}

ChannelOptionsSpec parse_channel_options(const YamlFile& src, const YAML::Node& node) {
  YamlMap m(src, node, "channel_options");
  ChannelOptionsSpec c;
  c.source_line = src.line(node);
  if (auto n = m.get("candidates")) {
    const std::string v = src.scalar(*n, m.field("candidates"));
    // "fast" is the former name of "exact" (raytrace/trace_options.h), still read.
    if (v != "exact" && v != "fast" && v != "exhaustive")
      throw src.error(*n, m.field("candidates"), "must be exact or exhaustive (got '" + clip(v) + "')");
    c.candidates = v;
  }
  if (auto n = m.get("candidate_rays")) {
    const long long v = src.integer(*n, m.field("candidate_rays"));
    if (v < 0 || v > 10'000'000)
      throw src.error(*n, m.field("candidate_rays"), "must be in 0…10000000 (got " + std::to_string(v) + ")");
    c.candidate_rays = static_cast<int>(v);
  }
  if (m.has("candidate_spread")) c.candidate_spread = m.positive({"candidate_spread"}, 1.0);
  if (m.has("drop_below_db")) c.drop_below_db = m.non_negative({"drop_below_db"}, 40.0);
  if (m.has("max_path_length_m")) c.max_path_length_m = m.positive({"max_path_length_m"}, 1.0);
  if (m.has("thin_post_max_width_m")) {
    const double w = m.non_negative({"thin_post_max_width_m"}, 0.15);
    if (w > 1.0) throw src.error(*m.get("thin_post_max_width_m"), m.field("thin_post_max_width_m"),
                                 "must be at most 1 m (a thin post is a fraction of a wavelength across)");
    c.thin_post_max_width_m = w;
  }
  if (m.has("double_diffraction_max_m")) {
    const double d = m.non_negative({"double_diffraction_max_m"}, 1.0);
    if (d > 100.0) throw src.error(*m.get("double_diffraction_max_m"), m.field("double_diffraction_max_m"),
                                   "must be at most 100 m");
    c.double_diffraction_max_m = d;
  }
  c.auto_phase_tolerance_rad = m.non_negative({"auto_phase_tolerance_rad"}, c.auto_phase_tolerance_rad);
  c.auto_rssi_tolerance_db = m.non_negative({"auto_rssi_tolerance_db"}, c.auto_rssi_tolerance_db);
  if (auto n = m.get("auto_sample_links")) {
    const long long v = src.integer(*n, m.field("auto_sample_links"));
    if (v < 1 || v > 10'000'000)
      throw src.error(*n, m.field("auto_sample_links"), "must be in 1…10000000 (got " + std::to_string(v) + ")");
    c.auto_sample_links = static_cast<size_t>(v);
  }
  m.finish();
  return c;
}

}  // namespace

Scenario parse_scenario(const std::string& text, const std::string& source) {
  const YamlFile src(source);
  const YAML::Node root = parse_yaml_text(text, source);
  if (!root.IsDefined() || root.IsNull()) throw InputError(source + ": empty scenario");
  YamlMap top(src, root, "");
  Scenario s;
  s.source = source;
  const std::filesystem::path base_dir = std::filesystem::path(source).parent_path();

  top.string("name", "");
  top.string("description", "");
  if (auto seed = top.get("seed")) {
    const long long v = src.integer(*seed, "seed");
    if (v < 0) throw src.error(*seed, "seed", "must be >= 0 (got " + std::to_string(v) + ")");
    s.seed = static_cast<uint64_t>(v);
  }
  if (top.has("duration_s")) s.duration_s = top.non_negative({"duration_s"}, 0.0);
  if (auto ch = top.get("channel")) {
    const std::string name = src.scalar(*ch, "channel");
    s.channel = src.located(*ch, [&] { return parse_channel_level(name, "channel"); });
  }
  if (auto co = top.get("channel_options")) s.channel_options = parse_channel_options(src, *co);
  const ReaderModelKind default_model =
      top.has("model") ? parse_model(src, *top.get("model"), "model") : ReaderModelKind::kPaper;
  if (auto scene = top.get("scene")) s.scene = parse_scene(src, *scene, base_dir);

  // Robots: `robot:` (one, named "robot" unless named) or `robots:` (a list).
  std::set<std::string> robot_names;
  if (auto one = top.get_one({"robot", "robots"})) {
    if (one->first == "robot") {
      s.robots.push_back(parse_robot(src, one->second, "robot"));
    } else {
      if (!one->second.IsSequence()) throw src.error(one->second, "robots", "must be a list");
      for (size_t i = 0; i < one->second.size(); ++i)
        s.robots.push_back(parse_robot(src, one->second[i], indexed("robots", i)));
    }
    for (const RobotSpec& r : s.robots)
      if (!robot_names.insert(r.name).second)
        throw InputError(src.file() + ":" + std::to_string(r.source_line) + ": field 'robots': duplicate name '" +
                         r.name + "'");
  }

  const YAML::Node antennas = top.required("antennas");
  if (!antennas.IsSequence() || antennas.size() == 0)
    throw src.error(antennas, "antennas", "must be a non-empty list");
  std::set<std::string> names;
  for (size_t i = 0; i < antennas.size(); ++i) {
    s.antennas.push_back(parse_antenna(src, antennas[i], indexed("antennas", i), i, default_model, robot_names));
    if (!names.insert(s.antennas.back().reader.name).second)
      throw src.error(antennas[i], indexed("antennas", i) + ".name",
                      "duplicate antenna name '" + s.antennas.back().reader.name + "'");
  }
  // Gen2 ports name antennas: resolved now that every antenna is known.
  for (size_t i = 0; i < s.antennas.size(); ++i) {
    if (!s.antennas[i].gen2) continue;
    for (size_t k = 0; k < s.antennas[i].gen2->ports.size(); ++k) {
      Gen2Port& port = s.antennas[i].gen2->ports[k];
      const auto it = std::find_if(s.antennas.begin(), s.antennas.end(),
                                   [&](const AntennaSpec& a) { return a.reader.name == port.antenna_name; });
      if (it == s.antennas.end())
        throw InputError(src.file() + ":" + std::to_string(port.source_line) + ": field '" +
                         indexed(indexed("antennas", i) + ".gen2.ports", k) + ".antenna': no antenna named '" +
                         clip(port.antenna_name) + "'");
      port.antenna = static_cast<size_t>(it - s.antennas.begin());
    }
  }
  if (auto tags = top.get("tags")) {
    if (!tags->IsSequence()) throw src.error(*tags, "tags", "must be a list");
    names.clear();
    for (size_t i = 0; i < tags->size(); ++i) {
      s.tags.push_back(parse_tag(src, (*tags)[i], indexed("tags", i), i));
      if (!names.insert(s.tags.back().tag.name).second)
        throw src.error((*tags)[i], indexed("tags", i) + ".name",
                        "duplicate tag name '" + s.tags.back().tag.name + "'");
    }
  }
  if (auto sets = top.get("tag_sets")) {
    if (!sets->IsSequence()) throw src.error(*sets, "tag_sets", "must be a list");
    std::vector<TagSetSpec> specs;
    bool need_scene = false;
    std::set<std::string> tag_names;
    for (const TagSpec& t : s.tags) tag_names.insert(t.tag.name);
    for (size_t i = 0; i < sets->size(); ++i) {
      specs.push_back(parse_tag_set(src, (*sets)[i], indexed("tag_sets", i)));
      need_scene = need_scene || specs.back().surface.has_value();
    }
    // Surface tags are laid on the scene's facets: load it here (the channel loads it again for tracing).
    std::shared_ptr<const Scene> scene;
    if (need_scene) {
      if (s.scene.meshes.empty()) throw src.error(*sets, "tag_sets", "surface tags need scene.meshes");
      scene = load_scene(s.scene, source);
    }
    size_t generated = 0;
    for (size_t i = 0; i < specs.size(); ++i) {
      std::vector<TagSpec> tags = src.located((*sets)[i], [&] {
        return generate_tags(specs[i], scene.get(), kMaxGeneratedTags - generated);
      });
      generated += tags.size();
      for (TagSpec& t : tags) {
        if (!tag_names.insert(t.tag.name).second)
          throw src.error((*sets)[i], indexed("tag_sets", i) + ".name",
                          "generates the tag name '" + t.tag.name + "', which already exists");
        s.tags.push_back(std::move(t));
      }
    }
  }
  // Phase ripples (core/phase_pattern.h) are hardware: drawn once per element from the scenario file's seed and
  // the element's index, so `simulate --seed` redraws the noise, not the tags.
  auto draw_ripple = [&](PhasePattern& p, uint64_t kind, uint64_t index) {
    if (!(p.ripple_rms_rad > 0.0)) return;
    Rng rng = make_stream(s.seed, {0x7269706c65ULL, kind, index});
    draw_phase_ripple(p, p.ripple_rms_rad, p.ripple_scale_rad, p.ripple_spread, rng);
  };
  for (size_t a = 0; a < s.antennas.size(); ++a) draw_ripple(s.antennas[a].reader.phase_pattern, 0, a);
  for (size_t i = 0; i < s.tags.size(); ++i) draw_ripple(s.tags[i].tag.phase_pattern, 1, i);
  top.finish();
  return s;
}

ReaderParams parse_reader_params(const YAML::Node& map, const std::string& where, const std::string& field,
                                 const ReaderParams& defaults) {
  const YamlFile src(where, false);
  YamlMap m(src, map, field);
  ReaderParams r = defaults;
  parse_reader_keys(m, map, r);
  m.finish();
  src.located(map, [&] {
    validate(r, field);
    return 0;
  });
  return r;
}

TagParams parse_tag_params(const YAML::Node& map, const std::string& where, const std::string& field,
                           const TagParams& defaults) {
  const YamlFile src(where, false);
  YamlMap m(src, map, field);
  TagParams t = defaults;
  parse_tag_keys(m, t);
  m.finish();
  src.located(map, [&] {
    validate(t, field);
    return 0;
  });
  return t;
}

Endpoint parse_endpoint(const YAML::Node& map, const std::string& where, const std::string& field) {
  const YamlFile src(where, false);
  YamlMap m(src, map, field);
  Endpoint e;
  e.pose.position = src.point(m.required("position"), m.field("position"));
  e.pose.orientation = parse_orientation(m);
  const double gain_dbi = m.number("gain_dbi", 0.0);
  e.pattern = m.has("pattern") ? parse_pattern(src, *m.get("pattern"), m.field("pattern"), gain_dbi)
                               : isotropic_pattern(gain_dbi);
  src.located(map, [&] {
    e.pattern.validate(m.field("pattern"));
    return 0;
  });
  if (auto pol = m.get("polarization")) e.polarization = parse_polarization(src, *pol, m.field("polarization"));
  m.finish();
  return e;
}

ChannelOptionsSpec parse_channel_options(const YAML::Node& map, const std::string& where) {
  const YamlFile src(where, false);
  return parse_channel_options(src, map);
}

Scenario load_scenario(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw InputError(path + ": cannot open scenario file (not a regular file)");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open scenario file (" + (std::filesystem::exists(path) ? "unreadable" : "no such file") + ")");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_scenario(text.str(), path);
}

}  // namespace rfidray::io
