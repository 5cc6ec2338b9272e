#pragma once
// The coverage CSV (`rfidray coverage`): header
//   antenna,x,y,z,read_probability,rssi_dbm,phase_error_rad,localization_bound_m,outside_validity,validity_error
// one row per (antenna, cell), antennas in scenario order, cells in their order (grid: x fastest, then y, then
// z). Positions in m (%.4f), probability %.6f, RSSI dB(m) %.3f, phase error rad %.5f, bound m %.6f, outside_validity
// 1 or 0 (%.0f), validity_error (a fraction of the free-space field) %.3f; a value that
// does not exist (planning/coverage_map.h: NaN) is an empty field. Fixed formats: the same numbers give the same bytes.
#include <ostream>
#include <string>
#include <vector>

#include "planning/coverage_map.h"

namespace rfidray::io {

inline constexpr const char* kCoverageCsvHeader =
    "antenna,x,y,z,read_probability,rssi_dbm,phase_error_rad,localization_bound_m,outside_validity,validity_error";

void write_coverage_csv(std::ostream& out, const std::vector<std::string>& antenna_names, const planning::CoverageCells& cells,
                        const std::vector<planning::CoverageValues>& values);

}  // namespace rfidray::io
