#pragma once
// RFID antennas and tags in SDF <sensor> elements, in two forms.
//
// The seed plugin's (Gazebo classic rfid_sensor):
//   <sensor name="reader" type="rfid">  <update_rate>15</update_rate>
//     <plugin name=".." filename="..">  frequency, noisephi, noiserssi, range, optional_distribution,
//       optional_distribution_params, communication_gain  </plugin> </sensor>
//   <sensor name=".." type="rfidtag"/>
// sdformat 12 does not know these types: it keeps the type string and copies the plugin children, which we
// read from the raw elements. Missing parameters get the seed plugin's own defaults (frequency 865.7 MHz,
// noisephi 0.1, noiserssi 0.005, range 5 m, communication_gain 250, no optional distribution), each reported;
// a missing or zero update_rate (Gazebo: every physics step) gets 15 Hz, reported.
//
// The native form: a custom sensor holding an <rfid_antenna> (or <rfid_tag>) element whose children are the
// keys of a scenario antenna (or tag) with YAML values, e.g. <model>physical</model>, <hopping>eu</hopping>,
// <pattern>{kind: patch, gain_dbi: 6}</pattern>; our defaults apply (io/scenario_yaml.h), unknown keys are errors.
//
// Either way the values go through the scenario parser (parse_reader_params / parse_tag_params), so names map
// and validate exactly as in YAML. An antenna is named by its sensor (its CSV file and ROS topic); a tag by
// its parent link's scoped name ("tag_1::link"), which is what the seed plugin publishes as Tag.name.
#include <sdf/Element.hh>
#include <string>
#include <vector>

#include "core/reader.h"

namespace rfidray::gazebo {

enum class RfidSensorKind { kNone, kAntenna, kTag };

// kNone for sensors that are not RFID (cameras, ...).
RfidSensorKind rfid_sensor_kind(const sdf::ElementPtr& sensor);

// `where` locates the sensor in messages ("world.sdf:72: sensor 'reader'"). Defaults applied are appended
// to `notes`, ignored elements to `warnings`. Throws InputError for bad values.
ReaderParams antenna_params(const sdf::ElementPtr& sensor, const std::string& where, std::vector<std::string>& notes,
                            std::vector<std::string>& warnings);
TagParams tag_params(const sdf::ElementPtr& sensor, const std::string& where, std::vector<std::string>& notes,
                     std::vector<std::string>& warnings);

// The TF frame the antenna is mounted in, for the ROS pose input (adapters/gazebo/ros_bridge.h): a <frame>
// child of the seed form's <plugin> or of <rfid_antenna>; "" when none. The sensor's <pose> is relative to it.
std::string antenna_tf_frame(const sdf::ElementPtr& sensor);

// The seed plugin's defaults for parameters a world leaves out.
ReaderParams seed_default_reader();

}  // namespace rfidray::gazebo
