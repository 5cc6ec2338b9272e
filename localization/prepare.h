#pragma once
// Turns one tag's raw reads into unwrapped relative range histories and runs the pre-checks every
// method shares (too few reads, aperture too short, undersampled).
#include <optional>
#include <vector>

#include "localization/observations.h"
#include "localization/options.h"
#include "localization/result.h"

namespace rfidray::loc {

// One unwrapped segment as relative ranges: range_m[k] = D_k + c (c unknown, one per segment), from
// r = Φ λ / (4π) (eq. 9: the round trip doubles the phase per metre).
struct RangeSegment {
  int group = 0;
  double wavelength_m = 0.0;
  std::vector<Vec3> antenna_m;
  std::vector<double> range_m;
};

struct PreparedTag {
  std::vector<RangeSegment> segments;   // usable segments only (≥ min_segment_reads)
  std::vector<Vec3> positions;          // antenna positions of all usable reads
  std::vector<Quat> orientations;       // same order
  int total_reads = 0, usable_reads = 0;
  int splits_step = 0, splits_gap = 0, splits_jump = 0;
  double path_aperture_m = 0.0;         // extent of all read positions
  double usable_aperture_m = 0.0;       // extent of the usable positions
  double median_step_m = 0.0;           // median antenna move between consecutive reads of a group
  Vec3 region_min = Vec3::Zero(), region_max = Vec3::Zero();  // search box (z fixed when height known)
};

// Largest distance between two points (two-sweep approximation: exact for paths that are nearly convex).
double extent_m(const std::vector<Vec3>& points);
// Largest angle (deg) under which `points` are seen from `x` (two-sweep approximation).
double aperture_angle_deg(const std::vector<Vec3>& points, const Vec3& x);

// Unwraps every group and checks the data; returns a failure when no method can work on it.
std::optional<LocalizeResult> prepare(const TagReads& tag, const LocalizeOptions& options, PreparedTag& out);

// Post-check shared by all methods: the path seen from the estimate under too small an angle.
std::optional<LocalizeResult> check_aperture_angle(const PreparedTag& prep, const Vec3& estimate,
                                                   const LocalizeOptions& options);

}  // namespace rfidray::loc
