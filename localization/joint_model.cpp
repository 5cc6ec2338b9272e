#include "localization/joint_model.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
#include <limits>
#include <map>

#include "core/units.h"
#include "localization/levenberg_marquardt.h"

namespace rfidray::loc {

namespace {
const AntennaCalibration* find_calibration(const JointModelOptions& o, const std::string& antenna) {
  if (!o.calibration) return nullptr;
  return o.calibration->antenna.empty() || o.calibration->antenna == antenna ? o.calibration : nullptr;
}
}  // namespace

JointModel::JointModel(const TagReads& tag, const JointModelOptions& options, bool fixed_z, double z_m)
    : fixed_z_(fixed_z), z_m_(z_m) {
  const double fold = options.fold_pi ? 2.0 : 1.0;
  std::map<std::string, int> antenna_group;
  lambda_min_ = std::numeric_limits<double>::infinity();
  carrier_calibrated_ = false;
  for (size_t g = 0; g < tag.groups.size(); ++g) {
    const ReadGroup& group = tag.groups[g];
    if (group.reads.empty()) continue;
    lambda_min_ = std::min(lambda_min_, wavelength_m(group.frequency_hz));
    const AntennaCalibration* cal = find_calibration(options, group.antenna);
    int offset_group;
    double carrier_offset = 0.0;
    const int ci = cal && cal->has_carrier_offsets() ? cal->carrier_index(group.frequency_hz) : -1;
    if (ci >= 0) {
      // Calibrated chain: one offset per antenna for all its carriers.
      carrier_offset = cal->carrier_offsets_rad[ci];
      auto [it, inserted] = antenna_group.try_emplace(group.antenna, groups_);
      if (inserted) ++groups_;
      offset_group = it->second;
      carrier_calibrated_ = true;
    } else {
      offset_group = groups_++;
    }
    const double k = fold * 4.0 * kPi / wavelength_m(group.frequency_hz);
    size_t start = 0;
    while (start < group.reads.size()) {
      size_t end = start + 1;
      while (end < group.reads.size() &&
             (group.reads[end].antenna_m - group.reads[start].antenna_m).norm() <= options.stop_tolerance_m)
        ++end;
      std::complex<double> sum = 0.0;
      double t = 0.0;
      for (size_t i = start; i < end; ++i) {
        sum += std::polar(1.0, fold * (group.reads[i].phase_rad - carrier_offset));
        t += group.reads[i].time_s;
      }
      const int n = static_cast<int>(end - start);
      const double rbar = std::abs(sum) / n;
      // Circular variance of one read: −2 ln R̄ (wrapped normal); one read: the nominal σ.
      double var = n >= 2 ? std::max(-2.0 * std::log(std::max(rbar, 1e-12)), 0.0) / n
                          : std::pow(fold * options.read_sigma_rad, 2);
      var += std::pow(fold * options.floor_sigma_rad, 2);
      JointPoint p;
      p.orientation = group.reads[start].antenna_orientation;
      p.antenna_m = cal ? cal->phase_centre(group.reads[start].antenna_m, p.orientation) : group.reads[start].antenna_m;
      p.k_rad_m = k;
      p.phase_rad = rbar > 0.0 ? std::arg(sum) : 0.0;
      p.weight = 1.0 / var;
      p.time_s = t / n;
      p.offset_group = offset_group;
      p.reads = n;
      p.calibration = cal;
      points_.push_back(p);
      reads_ += n;
      start = end;
    }
  }
  if (!std::isfinite(lambda_min_)) lambda_min_ = 0.0;
  fold_ = fold;
  const int n = point_count();
  antenna_x_.resize(n), antenna_y_.resize(n), antenna_z_.resize(n);
  k_rad_m_.resize(n), phase_rad_.resize(n), weight_.resize(n);
  group_of_.resize(n);
  for (int i = 0; i < n; ++i) {
    const JointPoint& p = points_[i];
    antenna_x_[i] = p.antenna_m.x(), antenna_y_[i] = p.antenna_m.y(), antenna_z_[i] = p.antenna_m.z();
    k_rad_m_[i] = p.k_rad_m, phase_rad_[i] = p.phase_rad, weight_[i] = p.weight;
    group_of_[i] = p.offset_group;
    any_pattern_ = any_pattern_ || p.calibration != nullptr;
    if (runs_.empty() || runs_.back().group != p.offset_group) runs_.push_back({i, 0, p.offset_group});
    ++runs_.back().size;
  }
}

struct JointModel::Scratch {
  Eigen::ArrayXd dx, dy, dz, range, raw, w;
  Eigen::ArrayXf reduced, cos_a, sin_a;
  std::vector<std::complex<double>> z;
  std::vector<double> theta;
  std::vector<Vec3> dtheta, draw_dx;
};

namespace {
// The pattern phase's gradient with respect to the direction vector d (antenna frame, from the phase centre
// to the tag): ∂az/∂d = (−d_y, d_x, 0)/ρ², ∂el/∂d = (−d_z d_x/ρ, −d_z d_y/ρ, ρ)/|d|² (ρ = hypot(d_x, d_y)),
// and the basis derivatives ∂/∂az = (1, 0, 2az, el, 0) (0 where az is clamped), ∂/∂el = (0, 1, 0, az, 2el).
Vec3 pattern_gradient_local(const AntennaCalibration& c, const Vec3& d) {
  const double rho2 = d.x() * d.x() + d.y() * d.y(), rho = std::sqrt(rho2), r2 = d.squaredNorm();
  const double az = std::atan2(d.y(), d.x()), el = std::atan2(d.z(), rho);
  const bool clamped = std::abs(az) > kHalfPiRad;
  const double azc = std::clamp(az, -kHalfPiRad, kHalfPiRad);
  const std::array<double, kPatternTerms> d_az{clamped ? 0.0 : 1.0, 0.0, clamped ? 0.0 : 2.0 * azc,
                                               clamped ? 0.0 : el, 0.0};
  const std::array<double, kPatternTerms> d_el{0.0, 1.0, 0.0, azc, 2.0 * el};
  double dp_daz = 0.0, dp_del = 0.0;
  for (int t = 0; t < kPatternTerms; ++t) dp_daz += c.pattern_rad[t] * d_az[t], dp_del += c.pattern_rad[t] * d_el[t];
  const Vec3 daz_dd = rho2 > 0.0 ? Vec3(-d.y() / rho2, d.x() / rho2, 0.0) : Vec3::Zero();
  const Vec3 del_dd = rho > 0.0 ? Vec3(Vec3(-d.z() * d.x() / rho, -d.z() * d.y() / rho, rho) / r2) : Vec3::Zero();
  return dp_daz * daz_dd + dp_del * del_dd;
}
}  // namespace

double JointModel::phasors(const Vec3& x, const std::vector<double>* mask, Scratch& s) const {
  const int n = point_count();
  s.dx = x.x() - antenna_x_;
  s.dy = x.y() - antenna_y_;
  s.dz = x.z() - antenna_z_;
  s.range = (s.dx.square() + s.dy.square() + s.dz.square()).sqrt();
  s.raw = phase_rad_ - k_rad_m_ * s.range;
  if (any_pattern_)
    for (int i = 0; i < n; ++i) {
      const JointPoint& p = points_[i];
      if (!p.calibration) continue;
      double az, el;
      direction_in_frame(p.antenna_m, p.orientation, x, az, el);
      s.raw[i] -= fold_ * p.calibration->pattern_phase_rad(az, el);
    }
  s.w = weight_;
  if (mask) s.w *= Eigen::Map<const Eigen::ArrayXd>(mask->data(), n);
  // Reduce to [−π, π] in double, then single-precision packet cos/sin (see the header). Rounding to the
  // nearest integer by adding and subtracting 1.5·2^52 (exact for |a| < 2^51, round-half-even like
  // nearbyint) keeps the reduction in packets; Eigen's round() is a libm call per element without SSE4.1.
  constexpr double kRoundMagic = 6755399441055744.0;
  s.reduced = (s.raw - kTwoPi * ((s.raw * (1.0 / kTwoPi) + kRoundMagic) - kRoundMagic)).cast<float>();
  s.cos_a = s.reduced.cos();
  s.sin_a = s.reduced.sin();
  // Z_g summed over each run of consecutive points of one group, in packets (masked points weigh 0).
  s.z.assign(groups_, 0.0);
  double total_w = 0.0;
  for (const GroupRun& run : runs_) {
    const auto w = s.w.segment(run.begin, run.size);
    s.z[run.group] += std::complex<double>((w * s.cos_a.segment(run.begin, run.size).cast<double>()).sum(),
                                           (w * s.sin_a.segment(run.begin, run.size).cast<double>()).sum());
    total_w += w.sum();
  }
  return total_w;
}

Vec3 JointModel::to_position(const Eigen::VectorXd& u) const {
  return fixed_z_ ? Vec3(u[0], u[1], z_m_) : Vec3(u[0], u[1], u[2]);
}

Eigen::VectorXd JointModel::to_unknowns(const Vec3& x) const {
  if (fixed_z_) return Eigen::Vector2d(x.x(), x.y());
  return x;
}

double JointModel::coherence(const Vec3& x, const std::vector<double>* mask) const {
  thread_local Scratch scratch;
  const double total_w = phasors(x, mask, scratch);
  double sum = 0.0;
  for (const auto& v : scratch.z) sum += std::abs(v);
  return total_w > 0.0 ? sum / total_w : 0.0;
}

namespace {
// a − 2π·round(a / 2π) ∈ [−π, π]: the wrap of the hot loop (no fmod).
inline double wrap_near_zero(double a) { return a - kTwoPi * std::nearbyint(a / kTwoPi); }
}  // namespace

void JointModel::evaluate(const Vec3& x, Eigen::VectorXd& r, Eigen::MatrixXd* J, const std::vector<double>* mask) const {
  const int n = point_count(), m = dof();
  thread_local Scratch s;
  phasors(x, mask, s);
  r.setZero(n);
  if (J) J->setZero(n, m);
  // θ_g = arg Z_g. Its exact gradient: dθ = Im(dZ / Z) with dZ = Σ w_j j e^{jρ_j} dρ_j, dρ_j = ∂raw_j/∂x dx
  // (−k_j u_j, and the pattern's gradient with a calibration), so ∂θ_g/∂x = Σ_j w_j Re(e^{jρ_j} Z̄_g)
  // ∂raw_j/∂x / |Z_g|² (the weighted mean of ∂raw/∂x when the phasors agree).
  // The exact gradient gives Gauss–Newton its quadratic convergence near the optimum.
  s.theta.resize(groups_);
  for (int g = 0; g < groups_; ++g) s.theta[g] = std::arg(s.z[g]);
  auto unit = [&](int i) {
    const double d = s.range[i];
    return d > 0.0 ? Vec3(s.dx[i] / d, s.dy[i] / d, s.dz[i] / d) : Vec3::Zero();
  };
  // ∂raw_i/∂x = −k u_i − fold ∂pattern_i/∂x (the pattern's gradient in world axes: q ∇_d pattern).
  auto draw_dx = [&](int i) {
    Vec3 g = -k_rad_m_[i] * unit(i);
    const JointPoint& p = points_[i];
    if (p.calibration && s.range[i] > 0.0)
      g -= fold_ * (p.orientation *
                    pattern_gradient_local(*p.calibration, p.orientation.conjugate() * Vec3(s.dx[i], s.dy[i], s.dz[i])));
    return g;
  };
  if (J) {
    s.draw_dx.resize(n);
    s.dtheta.assign(groups_, Vec3::Zero());
    for (int i = 0; i < n; ++i) {
      const double w = s.w[i];
      if (w <= 0.0) continue;
      s.draw_dx[i] = any_pattern_ ? draw_dx(i) : Vec3(-k_rad_m_[i] * unit(i));
      const std::complex<double>& zg = s.z[group_of_[i]];
      const double re = s.cos_a[i] * zg.real() + s.sin_a[i] * zg.imag();  // Re(e^{jρ} Z̄_g)
      s.dtheta[group_of_[i]] += (w * re) * s.draw_dx[i];
    }
    for (int g = 0; g < groups_; ++g) {
      const double z2 = std::norm(s.z[g]);
      s.dtheta[g] = z2 > 0.0 ? Vec3(s.dtheta[g] / z2) : Vec3::Zero();
    }
  }
  for (int i = 0; i < n; ++i) {
    const double w = s.w[i];
    if (w <= 0.0) continue;
    const int g = group_of_[i];
    const double sw = std::sqrt(w);
    r[i] = sw * wrap_near_zero(s.raw[i] - s.theta[g]);
    if (J) {
      // ∂e/∂x = ∂raw/∂x − ∂θ_g/∂x.
      const Vec3 gvec = s.draw_dx[i] - s.dtheta[g];
      for (int c = 0; c < m; ++c) (*J)(i, c) = sw * gvec[c];
    }
  }
}

Eigen::MatrixXd JointModel::calibration_jacobian(const Vec3& x, const std::vector<double>* mask) const {
  const int n = point_count();
  thread_local Scratch s;
  phasors(x, mask, s);
  using Row = Eigen::Matrix<double, 1, kGeometryTerms>;
  // ∂raw_i/∂β, raw = φ − k R − fold·pattern(az, el). In the antenna frame the direction to x is
  // d = q⁻¹(x − P) − δ, so ∂d/∂δ = −I: ∂R/∂δ = −d̂ᵀ and ∂pattern/∂δ = −∂pattern/∂d; ∂pattern/∂β_t =
  // basis_t(az, el).
  std::vector<Row> draw(n, Row::Zero());
  std::vector<Row> dtheta(groups_, Row::Zero());
  for (int i = 0; i < n; ++i) {
    const JointPoint& p = points_[i];
    if (!p.calibration || s.w[i] <= 0.0 || !(s.range[i] > 0.0)) continue;
    const Vec3 d = p.orientation.conjugate() * Vec3(s.dx[i], s.dy[i], s.dz[i]);
    const auto basis = pattern_basis(std::atan2(d.y(), d.x()), std::atan2(d.z(), std::hypot(d.x(), d.y())));
    const Vec3 d_offset = k_rad_m_[i] * d / s.range[i] + fold_ * pattern_gradient_local(*p.calibration, d);
    for (int a = 0; a < 3; ++a) draw[i][a] = d_offset[a];
    for (int t = 0; t < kPatternTerms; ++t) draw[i][3 + t] = -fold_ * basis[t];
    // θ_g = arg Z_g moves with the raw phases as in evaluate(): ∂θ_g = Σ_j w_j Re(e^{jρ_j} Z̄_g) ∂raw_j / |Z_g|².
    const std::complex<double>& zg = s.z[group_of_[i]];
    dtheta[group_of_[i]] += (s.w[i] * (s.cos_a[i] * zg.real() + s.sin_a[i] * zg.imag())) * draw[i];
  }
  for (int g = 0; g < groups_; ++g) {
    const double z2 = std::norm(s.z[g]);
    dtheta[g] = z2 > 0.0 ? Row(dtheta[g] / z2) : Row::Zero();
  }
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, kGeometryTerms);
  for (int i = 0; i < n; ++i)
    if (points_[i].calibration && s.w[i] > 0.0) K.row(i) = std::sqrt(s.w[i]) * (draw[i] - dtheta[group_of_[i]]);
  return K;
}

double JointModel::cost(const Vec3& x, const std::vector<double>* mask) const {
  Eigen::VectorXd r;
  evaluate(x, r, nullptr, mask);
  return r.squaredNorm();
}

std::vector<double> JointModel::wrapped_residuals(const Vec3& x) const {
  Eigen::VectorXd r;
  evaluate(x, r, nullptr);
  std::vector<double> e(r.size());
  for (int i = 0; i < r.size(); ++i) e[i] = r[i] / std::sqrt(points_[i].weight);  // unmasked: w > 0
  return e;
}

JointLm joint_lm(const JointModel& model, const Vec3& start, int max_iterations, const std::vector<double>* mask) {
  // Wrapped residuals are O(1) rad: absolute step and gain tolerances, a gradient relative to the cost.
  LmTolerances tol;
  tol.gradient_abs = 1e-14;
  tol.gradient_rel = 1e-14;
  tol.step_abs = 1e-7;   // 0.1 µm: three orders below any position uncertainty the fit can claim
  tol.step_rel = 0.0;
  tol.gain_rel = 1e-12;
  tol.reject_abs = 1e-7;
  tol.reject_rel = 0.0;
  const LmSolution sol = levenberg_marquardt_core(
      model.to_unknowns(start),
      [&](const Eigen::VectorXd& u, Eigen::VectorXd& r, Eigen::MatrixXd* J) {
        model.evaluate(model.to_position(u), r, J, mask);
      },
      max_iterations, tol);
  JointLm out;
  out.position = model.to_position(sol.unknowns);
  out.cost = sol.cost;
  out.converged = sol.converged && out.position.allFinite();
  return out;
}

}  // namespace rfidray::loc
