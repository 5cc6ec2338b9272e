#pragma once
// Module io — owns the files: the checked YAML reader (checked_yaml.h), scenarios (this file), readings CSV,
// real reader logs (real_log.h) and recorded trajectories (trajectory_csv.h), the channel factory (level →
// channel), plots, and the hook through which an adapter supplies world files (world_source.h). Includes core/,
// raytrace/ and localization/.
//
// Scenario files (YAML). Every error is an InputError "FILE:LINE: field 'antennas[1].frequency': ..."; keys
// that are not part of the format are errors too (a typo must not silently fall back to a default).
//
// Top level:  name, description (free text) · seed (integer ≥ 0, default 1) · duration_s (default: until
//   the last robot / waypoint motion ends) · channel (ideal, … see `rfidray simulate --help`) · model
//   (default reader model of every antenna: paper | physical) · scene · robot | robots · antennas · tags
// scene:      meshes: [{file, material?, position?, rpy_deg?|yaw_deg?|quaternion?, scale?}] (file relative to
//   the scenario) · materials: [{name, relative_permittivity, conductivity_s_m, thickness_m?}] ·
//   material_map: {mesh material name: radio material} · default_material
// robot:      name · waypoints [[x, y(, z)], …] · speed_m_s | wheel_speed_rad_s · wheel_radius_m ·
//   track_width_m · turn_rate_rad_s | turn_wheel_speed_rad_s · initial_heading_deg · start_s
// antenna:    name · model · frequency (Hz; seed plugin name) | frequency_hz | frequencies_hz [..] | hopping: eu
//   · phase_offset_rad | phase_offsets_rad [..] · hop_dwell_s · tx_power_dbm · noisephi | noise_phi_rad ·
//   noiserssi | noise_rssi · noise_rssi_db · range | range_m · range_sigma · optional_distribution ·
//   optional_distribution_params · communication_gain · update_rate | update_rate_hz · phase_bits ·
//   rssi_resolution_db · sensitivity_dbm · modulation_factor · gain_dbi · pattern · polarization · start_s ·
//   hardware effects: phase_centre_offset_m [x,y,z] · phase_pattern {azimuth_rad, elevation_rad} ·
//   snr_at_sensitivity_db · read_probability (one value or one per frequency)
//   and where it is — one of: position (+ rpy_deg | yaw_deg | quaternion [x,y,z,w]) · robot: NAME with
//   mount: {position, rpy_deg…} · waypoints + speed_m_s; optionally mast: {z_min_m, z_max_m, speed_m_s,
//   start_s} (fixed or robot base).
// tag:        name · gain_dbi · chip_sensitivity_dbm · pattern · polarization · phase_pattern · start_s · position (+ orientation)
//   | waypoints + speed_m_s (+ orientation).
// tag_sets:   tags by the thousand (io/tag_generators.h), each: name (pattern with {i}, {ix}, {iy}, {iz}) · the tag
//   radio keys · grid: {min: [x,y,z], max: [x,y,z], step_m} (+ rpy_deg | yaw_deg | quaternion) | surface:
//   {material?, mesh? (shell patterns), facing? [x,y,z], facing_tolerance_deg? (10), within? {min, max}, offset_m? (0.05),
//   step_m? (0.2)}
#include <yaml-cpp/yaml.h>

#include <string>

#include "core/channel.h"
#include "core/scenario.h"

namespace rfidray::io {

// Reads and parses a scenario file.
Scenario load_scenario(const std::string& path);
// Parses scenario text; `source` names it in messages, relative mesh paths resolve against its directory.
Scenario parse_scenario(const std::string& text, const std::string& source);

// The radio keys of one antenna (every antenna key above except name, start_s and the place) or one tag
// (gain_dbi, chip_sensitivity_dbm, pattern, polarization) from a YAML map, checked and validated exactly as in
// a scenario file; keys that are absent keep the value in `defaults`. For front ends that are not scenario
// files (the SDF importer builds the map from XML elements): `where` starts every message
// ("world.sdf:42: sensor 'reader'"), `field` names the map ("reader").
ReaderParams parse_reader_params(const YAML::Node& map, const std::string& where, const std::string& field,
                                 const ReaderParams& defaults);
TagParams parse_tag_params(const YAML::Node& map, const std::string& where, const std::string& field,
                           const TagParams& defaults);

// One end of a link written as a scenario writes a fixed antenna or tag: `position` (required), `rpy_deg` |
// `yaw_deg` | `quaternion`, `pattern`, `polarization`, `gain_dbi` — isotropic 0 dBi and linear polarization
// along the local z axis unless given, the defaults of `rfidray link`. And `channel_options` (README table).
// For front ends that are not scenario files (the Python API builds the map from its arguments): nodes are
// unmarked, so every message starts with `where`, then names the field.
Endpoint parse_endpoint(const YAML::Node& map, const std::string& where, const std::string& field);
ChannelOptionsSpec parse_channel_options(const YAML::Node& map, const std::string& where);

// The EU channel plan of `hopping: eu` (ETSI EN 302 208 high-power channels), Hz.
inline const std::vector<double>& eu_channels_hz() {
  static const std::vector<double> c{865.7e6, 866.3e6, 866.9e6, 867.5e6};
  return c;
}

}  // namespace rfidray::io
