#pragma once
// Straight legs between waypoints at constant speed with a fixed orientation: a tag on a moving object
// (tracking) or a hand-carried antenna. Starts moving at start_s, rests at the last waypoint afterwards.
#include <vector>

#include "core/trajectory.h"

namespace rfidray {

class WaypointTrajectory final : public Trajectory {
 public:
  // Throws InputError for no waypoints, non-finite values or a non-positive speed (with > 1 waypoint).
  WaypointTrajectory(std::vector<Vec3> waypoints, double speed_m_s, const Quat& orientation, double start_s = 0.0);
  Pose pose_at(double t_s) const override;
  bool is_static() const override { return cumulative_m_.back() == 0.0; }
  double end_time_s() const override { return is_static() ? 0.0 : start_s_ + cumulative_m_.back() / speed_m_s_; }

 private:
  std::vector<Vec3> waypoints_;
  std::vector<double> cumulative_m_;  // arc length at each waypoint
  double speed_m_s_;
  Quat orientation_;
  double start_s_;
};

}  // namespace rfidray
