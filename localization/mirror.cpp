#include "localization/mirror.h"

#include <Eigen/Eigenvalues>
#include <sstream>

namespace rfidray::loc {

bool reflect_across_path(const std::vector<Vec3>& positions, bool height_known, const Vec3& x, Vec3& out) {
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : positions) mean += p;
  mean /= static_cast<double>(positions.size());
  if (height_known) {
    Eigen::Matrix2d C = Eigen::Matrix2d::Zero();
    for (const Vec3& p : positions) {
      const Eigen::Vector2d d = (p - mean).head<2>();
      C += d * d.transpose();
    }
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> es(C);
    const Eigen::Vector2d dir = es.eigenvectors().col(1);  // principal direction
    const Eigen::Vector2d d = (x - mean).head<2>();
    const Eigen::Vector2d reflected = 2.0 * d.dot(dir) * dir - d;
    out = Vec3(mean.x() + reflected.x(), mean.y() + reflected.y(), x.z());
    return true;
  }
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();
  for (const Vec3& p : positions) C += (p - mean) * (p - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(C);
  const Eigen::Vector3d ev = es.eigenvalues();  // ascending
  // Collinear: the second eigenvalue (spread across the line) is negligible against the first.
  if (ev[1] <= 1e-6 * ev[2]) return false;
  const Vec3 normal = es.eigenvectors().col(0);
  out = x - 2.0 * (x - mean).dot(normal) * normal;
  return true;
}

MirrorCheck check_mirror(const std::vector<Vec3>& positions, const Vec3& estimate, const Objective& objective,
                         const LocalizeOptions& options, double noise_floor) {
  MirrorCheck check;
  Vec3 reflected;
  if (!reflect_across_path(positions, options.height_known, estimate, reflected)) {
    check.degenerate = check.ambiguous = true;
    return check;
  }
  // An estimate on the path's line/plane is its own mirror: nothing to tell apart.
  if ((reflected - estimate).norm() < 2.0 * options.cluster_bandwidth_m) return check;
  check.mirror = objective.refine(reflected);
  if ((check.mirror - estimate).norm() < 2.0 * options.cluster_bandwidth_m) return check;
  // A candidate that ran off the search region (or to NaN) is no alternative solution.
  const double tol = 1e-6;
  if (!check.mirror.allFinite() || (check.mirror.array() < objective.region_min.array() - tol).any() ||
      (check.mirror.array() > objective.region_max.array() + tol).any())
    return check;
  // Compare like with like: both candidates re-converged by the same local optimiser (a method's own
  // estimate need not be the least-squares optimum, e.g. the hyperbolic cluster mode).
  const double best = objective.ssr(objective.refine(estimate));
  const double other = objective.ssr(check.mirror);
  const int dof_left = std::max(1, objective.residuals - objective.dof);
  const double sigma2 = std::max(best / dof_left, noise_floor * noise_floor);
  check.delta_chi2 = (other - best) / sigma2;
  check.ambiguous = check.delta_chi2 < options.mirror_chi2;
  return check;
}

void settle_mirror(LocalizeResult& result, const MirrorCheck& check, const std::vector<Vec3>& positions,
                   const std::vector<Quat>& orientations, const LocalizeOptions& options) {
  if (!result.ok || !check.ambiguous) return;
  if (check.degenerate) {
    result.fail_without_position(FailReason::kAmbiguousMirror,
                                 "straight antenna path in 3-D: the tag can be anywhere on a circle around it");
    return;
  }
  std::ostringstream why;
  why << "mirror candidate (" << check.mirror.x() << ", " << check.mirror.y() << ", " << check.mirror.z()
      << ") fits within " << check.delta_chi2 << " chi2 units of the estimate";
  switch (options.mirror_prior) {
    case MirrorPrior::kNone:  // two positions fit equally: neither is reported
      result.fail_without_position(FailReason::kAmbiguousMirror, why.str());
      return;
    case MirrorPrior::kBoresight: {
      // Score = mean cosine between the boresight (local +X) and the direction to the candidate.
      auto score = [&](const Vec3& x) {
        double s = 0.0;
        for (size_t i = 0; i < positions.size(); ++i) {
          const Vec3 d = (x - positions[i]).normalized();
          s += (orientations[i] * Vec3::UnitX()).dot(d);
        }
        return s;
      };
      if (score(check.mirror) > score(result.position)) result.position = check.mirror;
      result.mirror_resolved_by = "boresight";
      return;
    }
    case MirrorPrior::kPoint:
      if ((check.mirror - options.prior_point).norm() < (result.position - options.prior_point).norm())
        result.position = check.mirror;
      result.mirror_resolved_by = "prior_point";
      return;
  }
}

}  // namespace rfidray::loc
