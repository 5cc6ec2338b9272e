#include "core/mast.h"

#include <cmath>
#include <string>

#include "core/error.h"

namespace rfidray {

double mast_height_m(const MastParams& p, double t_s) {
  const double span = p.z_max_m - p.z_min_m;
  const double tau = t_s - p.start_s;
  if (span <= 0.0 || tau <= 0.0) return p.z_min_m;
  const double period = mast_period_s(p);
  const double phase = std::fmod(tau, period);
  const double half = period / 2.0;
  return phase < half ? p.z_min_m + p.speed_m_s * phase : p.z_max_m - p.speed_m_s * (phase - half);
}

MastTrajectory::MastTrajectory(TrajectoryPtr base, const MastParams& p) : base_(std::move(base)), params_(p) {
  if (!std::isfinite(p.z_min_m) || !std::isfinite(p.z_max_m) || !std::isfinite(p.start_s))
    throw InputError("mast: z_min, z_max and start must be finite");
  if (p.z_max_m < p.z_min_m)
    throw InputError("mast: z_max (" + std::to_string(p.z_max_m) + ") must be >= z_min (" +
                     std::to_string(p.z_min_m) + ")");
  if (!(p.speed_m_s > 0.0) || !std::isfinite(p.speed_m_s))
    throw InputError("mast: speed must be > 0 (got " + std::to_string(p.speed_m_s) + ")");
}

Pose MastTrajectory::pose_at(double t_s) const {
  return base_->pose_at(t_s).compose(Pose{Vec3(0.0, 0.0, mast_height_m(params_, t_s)), Quat::Identity()});
}

}  // namespace rfidray
