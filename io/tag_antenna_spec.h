#pragma once
// The text forms of a tag's antenna, chip and backing (core/tag_antenna.h), shared by the scenario file and the
// command line (docs/tag-antenna.md):
//   antenna: dipole:LENGTH_M:RADIUS_M[:CONDUCTIVITY_S_M] | table:FILE.csv
//   chip:    matched[:DESIGN_FREQUENCY_HZ] | series:R_OHM:C_F | parallel:R_OHM:C_F
//   backing: none | scene | MATERIAL:DISTANCE_M | dielectric:EPS_R:SIGMA_S_M:DISTANCE_M
//            (MATERIAL: a built-in radio material, core/material.h: metal, water, wood, glass, …)
// A table file is CSV with a header line and the columns frequency_hz, resistance_ohm, reactance_ohm (the
// antenna's free-space impedance, e.g. from a datasheet or a NEC run), frequencies increasing.
// Throws InputError naming `field` (and for a table, its file and line). Thread-safe.
#include <string>
#include <vector>

#include "core/tag_antenna.h"

namespace rfidray::io {

TagAntennaSpec parse_tag_antenna(const std::string& text, const std::string& field);
TagChipSpec parse_tag_chip(const std::string& text, const std::string& field);
TagBackingSpec parse_tag_backing(const std::string& text, const std::string& field);
// The rows of a table file (see above).
std::vector<TagAntennaSpec::Point> read_tag_antenna_table(const std::string& file);

}  // namespace rfidray::io
