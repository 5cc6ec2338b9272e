#pragma once
// A recorded antenna trajectory (e.g. exported from a ROS bag) and its interpolation, for `rfidray import`.
// File: CSV with the header time,x,y,z,qx,qy,qz,qw (names case-insensitive, in any order, other columns
// ignored; without qx..qw every orientation is the identity). time in s, position in m, orientation a
// quaternion x,y,z,w (normalized on reading; any sign). Times must not decrease; two samples at one time must
// hold the same pose. A UTF-8 BOM and blank lines are skipped.
// pose_at(t): position linear in t, orientation by slerp (Eigen's shortest-arc Quaterniond::slerp), between
// the two samples around t. Stop-and-go recordings (several samples at one position) are fine: the interval
// used always has a positive length.
// Errors are InputError: reading names "FILE:LINE: column 'NAME': what" (or "FILE: empty file"); pose_at names
// the time and by how much it lies outside the recorded span. Immutable after construction, thread-safe.
#include <filesystem>
#include <string>
#include <vector>

#include "core/geometry.h"

namespace rfidray::io {

struct TrajectorySample {
  double time_s = 0.0;
  Pose pose;
  int line = 0;  // 1-based line in the file (0 when built in code)
};

class RecordedTrajectory {
 public:
  // Validates the samples (at least one; times finite and not decreasing; equal times hold equal poses).
  // `source` names them in messages (the file).
  RecordedTrajectory(std::string source, std::vector<TrajectorySample> samples);

  // The interpolated pose at time_s. A time up to tolerance_s outside [start_s, end_s] takes the nearest end's
  // pose; further out it throws InputError "time T s is D s before the start of the trajectory (SOURCE: A .. B s)"
  // (or "after the end").
  Pose pose_at(double time_s, double tolerance_s = 0.0) const;

  double start_s() const { return samples_.front().time_s; }
  double end_s() const { return samples_.back().time_s; }
  const std::string& source() const { return source_; }
  const std::vector<TrajectorySample>& samples() const { return samples_; }

 private:
  std::string source_;
  std::vector<TrajectorySample> samples_;
};

RecordedTrajectory read_trajectory_csv(const std::filesystem::path& file);

// Roll, pitch, yaw in radians about the fixed X, Y, Z axes, applied in that order (as `rpy_deg` in scenarios).
Quat quat_from_rpy(const Vec3& rpy_rad);

}  // namespace rfidray::io
