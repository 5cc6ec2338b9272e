#pragma once
// The antenna file: one AntennaCalibration (localization/antenna_calibration.h) as YAML, written by
// `rfidray calibrate` and read by `rfidray localize --antenna-file`. Layout (all keys required except the
// *_sd_* ones, which default to 0, and geometry_covariance; unknown keys are rejected; numbers must be finite):
//   antenna: a0
//   phase_centre_offset_m: [x, y, z]          # antenna frame, boresight = +X
//   phase_centre_offset_sd_m: [x, y, z]
//   frequencies_hz: [f0, f1, ...]             # ascending, distinct; carrier_offsets_rad[0] must be 0; []: no
//                                             # carrier calibrated (each keeps its own offset)
//   carrier_offsets_rad: [0, c1, ...]
//   carrier_offsets_sd_rad: [0, s1, ...]
//   pattern_terms: [az, el, az2, az_el, el2]  # must be exactly these (the basis of the coefficients)
//   pattern_rad: [b0, b1, b2, b3, b4]
//   pattern_sd_rad: [...]
//   geometry_covariance: [[8 numbers] × 8]    # optional: covariance of dx, dy, dz (m), az, el, az2, az_el,
//                                             # el2 (rad); symmetric, positive semi-definite
//   not_fitted: [{term: dz, why: "..."}]     # optional: geometry terms held at 0, the data could not tell them
//   prior_bounded: [{term: ..., why: "..."}] # optional: fitted terms whose sd is nearly the prior's
//   carrier_offsets_not_fitted: "..."        # optional, only with frequencies_hz: []: why none was kept
//   allowance: {base_rad: b, smooth_factor: f, samples: n, coverage: c,   # optional: measured radius allowance
//               bands: [{spacing_from_m, spacing_below_m, base_rad, smooth_factor, samples, coverage}]}
//                                             # bands optional: the same per band of tag spacing
//   residual_rms_rad: r                       # optional (absent: nothing was fitted)
//   reads_used: n
//   tags_used: n
// Errors: InputError "FILE:LINE: field 'x': what". Writing is deterministic (%.10g numbers).
#include <ostream>
#include <string>
#include <vector>

#include "localization/antenna_calibration.h"
#include "localization/observations.h"

namespace rfidray::io {

loc::AntennaCalibration read_antenna_file(const std::string& path);
loc::AntennaCalibration parse_antenna_yaml(const std::string& text, const std::string& source);
void write_antenna_file(std::ostream& out, const loc::AntennaCalibration& calibration);

// group_by_tag (readings_csv.h) labels each ReadGroup "fileN[:ANTENNA][/HOP]"; a calibration is per antenna
// name: this sets every group's `antenna` to ANTENNA ("" when the file has no antenna column). Groups stay
// separate (one per file, antenna, hop, frequency).
void label_groups_by_antenna(std::vector<loc::TagReads>& tags);

}  // namespace rfidray::io
