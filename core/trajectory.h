#pragma once
// Motion of antennas and tags: a pose as a function of simulation time. Trajectories compose (an antenna on
// a mast on a robot), so each concept is one small class behind this interface.
#include <limits>
#include <memory>

#include "core/geometry.h"

namespace rfidray {

class Trajectory {
 public:
  virtual ~Trajectory() = default;
  // World pose at time t_s (seconds of simulation time). Before its start a trajectory holds its first
  // pose, after its end its last one.
  virtual Pose pose_at(double t_s) const = 0;
  // True when pose_at is the same for every t (lets the simulation compute static links once).
  virtual bool is_static() const = 0;
  // Time from which the pose no longer changes: 0 for static, +inf for motion that never settles (a mast).
  virtual double end_time_s() const = 0;
};

using TrajectoryPtr = std::shared_ptr<const Trajectory>;

inline constexpr double kNeverSettles = std::numeric_limits<double>::infinity();

// A fixed pose.
class StaticTrajectory final : public Trajectory {
 public:
  explicit StaticTrajectory(const Pose& pose) : pose_(pose) {}
  Pose pose_at(double) const override { return pose_; }
  bool is_static() const override { return true; }
  double end_time_s() const override { return 0.0; }

 private:
  Pose pose_;
};

// A rigid mounting offset on a moving base: world = base(t) ∘ offset (e.g. the antenna on the robot).
class MountedTrajectory final : public Trajectory {
 public:
  MountedTrajectory(TrajectoryPtr base, const Pose& offset) : base_(std::move(base)), offset_(offset) {}
  Pose pose_at(double t_s) const override { return base_->pose_at(t_s).compose(offset_); }
  bool is_static() const override { return base_->is_static(); }
  double end_time_s() const override { return base_->end_time_s(); }

 private:
  TrajectoryPtr base_;
  Pose offset_;
};

}  // namespace rfidray
