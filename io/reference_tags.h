#pragma once
// Reference tags for `rfidray calibrate` and Python's `calibrate`: the reads of every tag whose position is
// known, as calibration samples (localization/calibration.h). Plain functions; thread-safe; throw InputError.
#include <map>
#include <set>
#include <string>
#include <vector>

#include "core/geometry.h"
#include "io/readings_csv.h"
#include "localization/calibration.h"

namespace rfidray::io {

// The tags of one run (one readings file) that `truth` (name → position, m) knows, grouped per antenna and
// carrier as localize groups them; tags without a known position are no reference and are skipped. Adds the
// antennas that read them to `antennas`.
void add_reference_tags(const std::vector<ReadingRow>& rows, const std::map<std::string, Vec3>& truth,
                        std::vector<loc::CalibrationSample>& samples, std::set<std::string>& antennas);

// The antenna to calibrate: `requested` when given, else the only one that read a reference tag. Throws
// InputError naming `field` when there are several (or none).
std::string antenna_to_calibrate(const std::string& requested, const std::set<std::string>& antennas,
                                 const std::string& field);

}  // namespace rfidray::io
