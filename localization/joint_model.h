#pragma once
// The joint multi-carrier phase model of one tag. Every (antenna, carrier) group g has its own unknown phase
// offset θ_g, but all groups constrain the one position p:
//   φ_i ≈ θ_g + k_g R_i(p) + pattern_i(p)  (mod 2π),   k_g = 4π f_g / c,  R_i = |p − a_i|.
// Stop-and-go data (many reads at one antenna position) are reduced to one circular mean per (group, stop)
// with its own dispersion: var_i = s_i² / n_i + floor², s_i² = −2 ln |mean e^{jφ}| (circular variance of one
// read), weight w_i = 1 / var_i. Offsets are eliminated in closed form: for a position p the optimal θ_g is
// the angle of Z_g = Σ_{i∈g} w_i e^{j(φ_i − k_g R_i − pattern_i)}. The coherent score Σ_g |Z_g| / Σ w is the
// SAR matched filter of the joint model (used on grids); the weighted wrapped residuals
// e_i = wrap(φ_i − k_g R_i − pattern_i − θ_g) are what Gauss–Newton / LM minimise.
// With a calibration (antenna_calibration.h): antenna positions move to the phase centre, the pattern phase is
// predicted, and when the carrier offsets are calibrated they are removed and each antenna has ONE offset for
// all its carriers, so that the carrier slope ∂φ/∂f = 4πR/c carries range.
// fold_pi: readers with a π ambiguity — phases are doubled (φ → 2φ, k → 2k), which removes it.
// Evaluation: ranges, phases and wraps in double; each stop's phasor e^{j(φ − kR − pattern − 2πm)} from the
// argument reduced to [−π, π] in double, then cos/sin in single precision, vectorised (Eigen's packet
// sin/cos): |error| ≲ 1e-7 rad, six orders below any phase noise a reader has, and the phasors are summed in
// double. The wrapped residuals themselves stay in double.
// Thread-safe for concurrent const use (per-thread scratch buffers).
#include <Eigen/Dense>
#include <string>
#include <vector>

#include "localization/antenna_calibration.h"
#include "localization/observations.h"

namespace rfidray::loc {

struct JointPoint {
  Vec3 antenna_m = Vec3::Zero();   // phase centre (calibrated when a calibration applies)
  Quat orientation = Quat::Identity();
  double k_rad_m = 0.0;            // phase per metre of one-way range (4π/λ, doubled when folding π)
  double phase_rad = 0.0;          // circular mean of the stop (carrier offset removed when calibrated)
  double weight = 1.0;             // 1 / var
  double time_s = 0.0;             // mean time of the stop (orders the aperture for block resampling)
  int offset_group = 0;
  int reads = 1;
  const AntennaCalibration* calibration = nullptr;  // pattern to predict, or null
};

struct JointModelOptions {
  double stop_tolerance_m = 1e-3;   // consecutive reads within this antenna move are one stop
  double read_sigma_rad = 0.1;      // per-read σ assumed for stops of one read (no dispersion to measure)
  double floor_sigma_rad = 0.02;    // model-error floor added to every stop's variance
  bool fold_pi = false;
  // Applies to reads of the antenna of the same name (or to all reads when its name is empty); null: none.
  const AntennaCalibration* calibration = nullptr;
};

class JointModel {
 public:
  JointModel(const TagReads& tag, const JointModelOptions& options, bool fixed_z, double z_m);

  int point_count() const { return static_cast<int>(points_.size()); }
  int group_count() const { return groups_; }
  int dof() const { return fixed_z_ ? 2 : 3; }
  int reads() const { return reads_; }
  bool carrier_calibrated() const { return carrier_calibrated_; }
  const std::vector<JointPoint>& points() const { return points_; }
  double min_wavelength_m() const { return lambda_min_; }
  Vec3 to_position(const Eigen::VectorXd& u) const;
  Eigen::VectorXd to_unknowns(const Vec3& x) const;

  // Coherent score Σ_g |Z_g| / Σ w ∈ [0, 1]; mask (per point, a factor on its weight, 0 = left out; null:
  // all at 1) — robust reweighting and jackknife blocks.
  double coherence(const Vec3& x, const std::vector<double>* mask = nullptr) const;
  // Weighted wrapped residuals r_i = √w_i e_i (0 for masked-out points) and optionally J (n × dof).
  void evaluate(const Vec3& x, Eigen::VectorXd& r, Eigen::MatrixXd* J, const std::vector<double>* mask = nullptr) const;
  double cost(const Vec3& x, const std::vector<double>* mask = nullptr) const;  // Σ w e²
  // ∂r/∂β (n × kGeometryTerms) of the weighted residuals of evaluate() with respect to the calibration's
  // phase-centre offset and pattern coefficients β (antenna_calibration.h), the group offsets re-optimised
  // as in J; rows of points without a calibration are 0. Used to propagate the calibration's covariance.
  Eigen::MatrixXd calibration_jacobian(const Vec3& x, const std::vector<double>* mask = nullptr) const;
  // Unweighted wrapped residuals e_i (rad).
  std::vector<double> wrapped_residuals(const Vec3& x) const;

 private:
  std::vector<JointPoint> points_;
  // The same points as arrays for the vectorised evaluation.
  Eigen::ArrayXd antenna_x_, antenna_y_, antenna_z_, k_rad_m_, phase_rad_, weight_;
  std::vector<int> group_of_;
  struct GroupRun {
    int begin, size, group;
  };
  std::vector<GroupRun> runs_;  // maximal runs of consecutive points of one offset group
  bool any_pattern_ = false;
  int groups_ = 0, reads_ = 0;
  bool fixed_z_ = false, carrier_calibrated_ = false;
  double z_m_ = 0.0, lambda_min_ = 0.0, fold_ = 1.0;
  struct Scratch;
  // Fills the scratch's ranges, offsets d = x − a, raw phases φ − kR − pattern, effective weights
  // (weight · mask) and phasors; sums the phasors per group. Returns Σ effective weight.
  double phasors(const Vec3& x, const std::vector<double>* mask, Scratch& s) const;
};

struct JointLm {
  Vec3 position = Vec3::Zero();
  double cost = 0.0;
  bool converged = false;
};
// Levenberg–Marquardt on the weighted wrapped residuals from `start`.
JointLm joint_lm(const JointModel& model, const Vec3& start, int max_iterations, const std::vector<double>* mask = nullptr);

}  // namespace rfidray::loc
