#pragma once
// Antenna gain patterns, evaluated per path direction in the antenna's own frame.
// Convention: boresight is the local +X axis (ROS "forward"); for the dipole the wire is the local Z axis.
#include <memory>
#include <string>
#include <vector>

#include "core/geometry.h"

namespace rfidray {

enum class PatternKind { kIsotropic, kDipole, kPatch, kTable };

// Azimuth × elevation gain table in dBi. Azimuth is measured in the local XY plane from +X towards +Y,
// elevation from the XY plane towards +Z, both in degrees; bilinear interpolation of the dBi values,
// azimuth wraps across ±180° (a grid not spanning 360° is interpolated across the gap), elevation clamps.
struct PatternTable {
  std::vector<double> azimuth_deg;    // strictly increasing, within [-180, 180]
  std::vector<double> elevation_deg;  // strictly increasing, within [-90, 90]
  std::vector<double> gain_dbi;       // row-major [elevation][azimuth]
};

struct AntennaPattern {
  PatternKind kind = PatternKind::kIsotropic;
  double peak_gain_dbi = 0.0;       // isotropic: the gain in every direction; patch: boresight gain
  double beamwidth_deg = 0.0;       // patch: half-power beamwidth (0: derive the exponent from the gain)
  double front_to_back_db = 20.0;   // patch: gain floor behind the ground plane, relative to the peak
  std::shared_ptr<const PatternTable> table;  // kTable only

  // Linear power gain in a direction given in the antenna frame (need not be normalised).
  double gain_linear(const Vec3& direction_local) const;
  // Linear power gain in a world direction for an antenna with the given orientation.
  double gain_linear_world(const Quat& orientation, const Vec3& direction_world) const {
    if (kind == PatternKind::kIsotropic) return gain_linear(direction_world);  // no rotation needed
    return gain_linear(orientation.conjugate() * direction_world);
  }
  // The largest value gain_linear takes in any direction: a bound for sums and integrals over directions
  // (raytrace/edge_end_finder.cpp). A table's is its largest entry (bilinear in dBi never exceeds it): O(entries).
  double max_gain_linear() const;
  // Exponent n of the cos^n patch model (derived from beamwidth, or from the gain when no beamwidth).
  double patch_exponent() const;
  // Throws InputError naming `field` when parameters are out of range.
  void validate(const std::string& field) const;
};

AntennaPattern isotropic_pattern(double gain_dbi = 0.0);

PatternKind parse_pattern_kind(const std::string& name, const std::string& field);
const char* to_string(PatternKind kind);

}  // namespace rfidray
