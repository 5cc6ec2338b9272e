#include "core/waypoint_trajectory.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "core/error.h"

namespace rfidray {

WaypointTrajectory::WaypointTrajectory(std::vector<Vec3> waypoints, double speed_m_s, const Quat& orientation,
                                       double start_s)
    : waypoints_(std::move(waypoints)), speed_m_s_(speed_m_s), orientation_(orientation.normalized()),
      start_s_(start_s) {
  if (waypoints_.empty()) throw InputError("waypoints: need at least one");
  for (const Vec3& w : waypoints_)
    if (!w.allFinite()) throw InputError("waypoints: must be finite");
  if (!std::isfinite(start_s_)) throw InputError("waypoints: start time must be finite");
  cumulative_m_.assign(1, 0.0);
  for (size_t i = 1; i < waypoints_.size(); ++i)
    cumulative_m_.push_back(cumulative_m_.back() + (waypoints_[i] - waypoints_[i - 1]).norm());
  if (cumulative_m_.back() > 0.0 && (!(speed_m_s_ > 0.0) || !std::isfinite(speed_m_s_)))
    throw InputError("waypoints: speed must be > 0 (got " + std::to_string(speed_m_s_) + ")");
}

Pose WaypointTrajectory::pose_at(double t_s) const {
  const double total = cumulative_m_.back();
  const double s = std::clamp((t_s - start_s_) * speed_m_s_, 0.0, total);
  if (total == 0.0 || s <= 0.0) return Pose{waypoints_.front(), orientation_};
  if (s >= total) return Pose{waypoints_.back(), orientation_};
  // First waypoint whose arc length exceeds s: we are on the leg ending there.
  const size_t i = static_cast<size_t>(std::upper_bound(cumulative_m_.begin(), cumulative_m_.end(), s) -
                                       cumulative_m_.begin());
  const double leg = cumulative_m_[i] - cumulative_m_[i - 1];
  const double f = (s - cumulative_m_[i - 1]) / leg;
  return Pose{waypoints_[i - 1] + f * (waypoints_[i] - waypoints_[i - 1]), orientation_};
}

}  // namespace rfidray
