#pragma once
// Least-squares cost on the unwrapped relative ranges with the per-segment offsets eliminated in closed
// form (variable projection): for a tag at x, segment s, read k,
//   e_k = (m_k − m̄_s) − (D_k(x) − D̄_s(x)),   D_k(x) = |x − P_k|,
// where m_k = Φ_k λ/(4π) is the unwrapped phase distance and bars are segment means. The optimal offset of
// segment s is c_s = m̄_s − D̄_s, so minimising Σ e² over x equals minimising over (x, c_1..c_S).
#include <Eigen/Dense>
#include <vector>

#include "localization/prepare.h"

namespace rfidray::loc {

class RangeCost {
 public:
  // fixed_z: the 2-D case, x.z() is held at z_m and the unknowns are (x, y).
  RangeCost(const PreparedTag& prep, bool fixed_z, double z_m);
  int residual_count() const { return n_; }
  int dof() const { return fixed_z_ ? 2 : 3; }
  // Unknowns ↔ positions.
  Vec3 to_position(const Eigen::VectorXd& u) const;
  Eigen::VectorXd to_unknowns(const Vec3& x) const;
  // Sum of squared residuals (m²).
  double ssr(const Vec3& x) const;
  // Residuals (n) and, when J is non-null, the Jacobian (n × dof).
  void evaluate(const Vec3& x, Eigen::VectorXd& r, Eigen::MatrixXd* J) const;
  // The offset c_s of each segment at x (its unwrapped phase distance minus the geometric one).
  double offset_m(const Vec3& x, int segment) const;

 private:
  const PreparedTag& prep_;
  bool fixed_z_;
  double z_m_;
  int n_ = 0;
  // Stop-and-go data: consecutive reads of a segment at the same antenna position are one stop. ssr() sums
  // per stop: Σ_k (m_k − D − c)² = W_s + n_s (m̄_s − D − c)² (W_s the stop's own scatter), exact, and a stop
  // of a real reader holds ~100 reads.
  // Per segment, its stops as arrays (the coarse grid of NLLS evaluates ssr at up to 20 000 points).
  struct Stops {
    Eigen::ArrayXd x_m, y_m, z_m, reads, mean_range_m;
  };
  std::vector<Stops> stops_;  // per segment
  double within_stop_scatter_m2_ = 0.0;
};

// 1-σ position uncertainty sqrt(trace(σ²(JᵀJ)⁻¹)) at x for a range noise σ (m); infinite if singular.
double predicted_std_m(const RangeCost& cost, const Vec3& x, double sigma_m);

struct LmResult {
  Vec3 position = Vec3::Zero();
  double ssr = 0.0;
  int iterations = 0;
  bool converged = false;
};

// Levenberg–Marquardt (Marquardt's diagonal scaling, Nielsen's damping update) from `start`.
LmResult levenberg_marquardt(const RangeCost& cost, const Vec3& start, int max_iterations);

}  // namespace rfidray::loc
