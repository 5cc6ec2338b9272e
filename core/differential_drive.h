#pragma once
// A differential-drive (skid-steer equivalent) robot following waypoints on the floor, with the paper's
// kinematics (D'Avella et al. 2022, eq. 6–8):
//   Ẋ = v cos Θ,  Ẏ = v sin Θ,  Θ̇ = ω          (eq. 6 with v_y = 0, non-holonomic)
//   v = r (ω_R + ω_L) / 2                       (eq. 7)
//   ω = r (ω_R − ω_L) / d                       (eq. 8)
// At every corner the robot turns in place (ω_R = −ω_L) to face the next waypoint, then drives straight
// (ω_R = ω_L). Each segment has constant wheel speeds, so eq. 6 integrates in closed form per segment.
#include <vector>

#include "core/trajectory.h"

namespace rfidray {

struct WheelSpeeds {
  double left_rad_s = 0.0;
  double right_rad_s = 0.0;
};

// eq. 7 and eq. 8.
inline double body_speed_m_s(const WheelSpeeds& w, double wheel_radius_m) {
  return wheel_radius_m * (w.right_rad_s + w.left_rad_s) / 2.0;
}
inline double body_turn_rate_rad_s(const WheelSpeeds& w, double wheel_radius_m, double track_width_m) {
  return wheel_radius_m * (w.right_rad_s - w.left_rad_s) / track_width_m;
}
// Inverse of eq. 7–8: the wheel speeds that give body speed v and turn rate ω.
inline WheelSpeeds wheel_speeds_for(double v_m_s, double omega_rad_s, double wheel_radius_m, double track_width_m) {
  return {(v_m_s - omega_rad_s * track_width_m / 2.0) / wheel_radius_m,
          (v_m_s + omega_rad_s * track_width_m / 2.0) / wheel_radius_m};
}

struct DifferentialDriveParams {
  double wheel_radius_m = 0.1;
  double track_width_m = 0.4;
  double drive_wheel_speed_rad_s = 3.5;  // both wheels while driving straight: v = r·this (eq. 7)
  double turn_wheel_speed_rad_s = 2.0;   // |ω_R| = |ω_L| while turning in place: ω = 2r·this/d (eq. 8)
  double start_s = 0.0;                  // the robot rests at the first waypoint until then
  bool has_initial_heading = false;      // false: starts facing the first leg (no initial turn)
  double initial_heading_rad = 0.0;
};

// Robot state on the plane (the paper's q = [X, Y, Θ]).
struct PlanarState {
  double x_m = 0.0, y_m = 0.0, heading_rad = 0.0;
};

class DifferentialDriveTrajectory final : public Trajectory {
 public:
  // Waypoints: x, y on the floor; z is the constant height of the robot frame (normally 0). Throws
  // InputError for non-positive r, d, wheel speeds or non-finite waypoints.
  DifferentialDriveTrajectory(std::vector<Vec3> waypoints, const DifferentialDriveParams& params);

  Pose pose_at(double t_s) const override;
  bool is_static() const override { return segments_.empty(); }
  double end_time_s() const override;

  PlanarState state_at(double t_s) const;

  // One constant-wheel-speed piece: a turn in place or a straight drive.
  struct Segment {
    double t0_s = 0.0, t1_s = 0.0;
    PlanarState start;
    WheelSpeeds wheels;
    double v_m_s = 0.0, omega_rad_s = 0.0;  // from eq. 7–8
  };
  const std::vector<Segment>& segments() const { return segments_; }

 private:
  std::vector<Segment> segments_;
  PlanarState first_, last_;
  double z_m_ = 0.0;
  double start_s_ = 0.0;
};

// Closed-form solution of eq. 6 for constant v, ω over a time dt from `s`.
PlanarState integrate_unicycle(const PlanarState& s, double v_m_s, double omega_rad_s, double dt_s);

}  // namespace rfidray
