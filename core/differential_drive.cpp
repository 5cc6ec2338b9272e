#include "core/differential_drive.h"

#include <cmath>
#include <string>

#include "core/error.h"
#include "core/units.h"

namespace rfidray {

PlanarState integrate_unicycle(const PlanarState& s, double v, double omega, double dt) {
  PlanarState e;
  e.heading_rad = s.heading_rad + omega * dt;
  if (std::abs(omega * dt) < 1e-12) {
    e.x_m = s.x_m + v * dt * std::cos(s.heading_rad);
    e.y_m = s.y_m + v * dt * std::sin(s.heading_rad);
  } else {
    // ∫ v cos(Θ0 + ω τ) dτ = (v/ω)(sin Θ(t) − sin Θ0), likewise for sin.
    e.x_m = s.x_m + v / omega * (std::sin(e.heading_rad) - std::sin(s.heading_rad));
    e.y_m = s.y_m - v / omega * (std::cos(e.heading_rad) - std::cos(s.heading_rad));
  }
  return e;
}

DifferentialDriveTrajectory::DifferentialDriveTrajectory(std::vector<Vec3> waypoints,
                                                         const DifferentialDriveParams& p) {
  auto positive = [](double v, const char* name) {
    if (!(v > 0.0) || !std::isfinite(v))
      throw InputError(std::string("robot: ") + name + " must be > 0 (got " + std::to_string(v) + ")");
  };
  positive(p.wheel_radius_m, "wheel radius");
  positive(p.track_width_m, "track width");
  positive(p.drive_wheel_speed_rad_s, "drive wheel speed");
  positive(p.turn_wheel_speed_rad_s, "turn wheel speed");
  if (!std::isfinite(p.start_s)) throw InputError("robot: start time must be finite");
  if (waypoints.empty()) throw InputError("robot: needs at least one waypoint");
  for (const Vec3& w : waypoints)
    if (!w.allFinite()) throw InputError("robot: waypoints must be finite");

  start_s_ = p.start_s;
  z_m_ = waypoints.front().z();
  const WheelSpeeds drive{p.drive_wheel_speed_rad_s, p.drive_wheel_speed_rad_s};
  const double v = body_speed_m_s(drive, p.wheel_radius_m);

  PlanarState s{waypoints.front().x(), waypoints.front().y(), 0.0};
  bool heading_known = p.has_initial_heading;
  if (heading_known) s.heading_rad = p.initial_heading_rad;
  double t = p.start_s;
  for (size_t i = 1; i < waypoints.size(); ++i) {
    const double dx = waypoints[i].x() - s.x_m, dy = waypoints[i].y() - s.y_m;
    const double length = std::hypot(dx, dy);
    if (length < 1e-12) continue;  // repeated waypoint: nothing to do
    const double target = std::atan2(dy, dx);
    if (!heading_known) {
      s.heading_rad = target;
      heading_known = true;
    }
    const double turn = wrap_to_pi(target - s.heading_rad);
    if (std::abs(turn) > 1e-12) {
      // Turn in place: ω_R = ±w, ω_L = ∓w  →  v = 0, |ω| = 2 r w / d.
      const double w = turn > 0.0 ? p.turn_wheel_speed_rad_s : -p.turn_wheel_speed_rad_s;
      Segment seg;
      seg.wheels = {-w, w};
      seg.v_m_s = body_speed_m_s(seg.wheels, p.wheel_radius_m);
      seg.omega_rad_s = body_turn_rate_rad_s(seg.wheels, p.wheel_radius_m, p.track_width_m);
      seg.start = s;
      seg.t0_s = t;
      seg.t1_s = t + turn / seg.omega_rad_s;
      segments_.push_back(seg);
      t = seg.t1_s;
      s.heading_rad = target;  // exact, no accumulated rounding
    }
    Segment seg;
    seg.wheels = drive;
    seg.v_m_s = v;
    seg.omega_rad_s = 0.0;
    seg.start = s;
    seg.t0_s = t;
    seg.t1_s = t + length / v;
    segments_.push_back(seg);
    t = seg.t1_s;
    s.x_m = waypoints[i].x();  // end exactly on the waypoint
    s.y_m = waypoints[i].y();
  }
  // A robot that never moves still has a defined heading.
  if (!heading_known) s.heading_rad = 0.0;
  first_ = segments_.empty() ? s : segments_.front().start;
  last_ = s;
}

double DifferentialDriveTrajectory::end_time_s() const {
  return segments_.empty() ? 0.0 : segments_.back().t1_s;
}

PlanarState DifferentialDriveTrajectory::state_at(double t_s) const {
  if (segments_.empty() || t_s <= segments_.front().t0_s) return first_;
  if (t_s >= segments_.back().t1_s) return last_;
  // Segments are few (two per waypoint); a binary search keeps long routes cheap.
  size_t lo = 0, hi = segments_.size() - 1;
  while (lo < hi) {
    const size_t mid = (lo + hi + 1) / 2;
    if (segments_[mid].t0_s <= t_s) lo = mid; else hi = mid - 1;
  }
  const Segment& seg = segments_[lo];
  return integrate_unicycle(seg.start, seg.v_m_s, seg.omega_rad_s, t_s - seg.t0_s);
}

Pose DifferentialDriveTrajectory::pose_at(double t_s) const {
  const PlanarState s = state_at(t_s);
  return Pose{Vec3(s.x_m, s.y_m, z_m_), Quat(Eigen::AngleAxisd(s.heading_rad, Vec3::UnitZ()))};
}

}  // namespace rfidray
