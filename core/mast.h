#pragma once
// A vertical mast (paper Fig. 11: the antenna moves up and down on the robot): the height above the base
// sweeps [z_min, z_max] at constant speed, starting at z_min going up, as a triangle wave of period
// 2 (z_max − z_min) / speed. world = base(t) ∘ translation(0, 0, z(t)); mount offsets compose on top.
#include "core/trajectory.h"

namespace rfidray {

struct MastParams {
  double z_min_m = 0.0;
  double z_max_m = 1.5;
  double speed_m_s = 0.1;
  double start_s = 0.0;  // the mast rests at z_min until then
};

// Height of the mast at t_s; throws nothing (params are validated by MastTrajectory).
double mast_height_m(const MastParams& p, double t_s);
inline double mast_period_s(const MastParams& p) { return 2.0 * (p.z_max_m - p.z_min_m) / p.speed_m_s; }

class MastTrajectory final : public Trajectory {
 public:
  // Throws InputError unless z_min ≤ z_max, speed > 0, all finite.
  MastTrajectory(TrajectoryPtr base, const MastParams& params);
  Pose pose_at(double t_s) const override;
  bool is_static() const override { return base_->is_static() && params_.z_max_m == params_.z_min_m; }
  double end_time_s() const override {
    return params_.z_max_m == params_.z_min_m ? base_->end_time_s() : kNeverSettles;
  }

 private:
  TrajectoryPtr base_;
  MastParams params_;
};

}  // namespace rfidray
