#include "localization/calibration.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <complex>
#include <map>

#include "core/error.h"
#include "core/units.h"
#include "localization/joint_model.h"

namespace rfidray::loc {

namespace {

struct CalPoint {
  Vec3 antenna_m;
  Quat orientation;
  double k_rad_m;
  double phase_rad;
  double weight;
  int carrier;
  int sample;
};

// Parameter layout: [δx, δy, δz, c_1 .. c_{F−1}, β_0 .. β_{T−1}]; `free` lists the fitted ones.
struct Layout {
  int carriers = 1;
  int size() const { return 3 + (carriers - 1) + kPatternTerms; }
  int carrier(int f) const { return 3 + f - 1; }
  int pattern(int t) const { return 3 + carriers - 1 + t; }
};

class CalProblem {
 public:
  CalProblem(std::vector<CalPoint> points, int samples, Layout layout, double fold)
      : points_(std::move(points)), samples_(samples), layout_(layout), fold_(fold) {}
  int size() const { return static_cast<int>(points_.size()); }

  // Weighted wrapped residuals √w e at parameters θ (ν per sample eliminated).
  Eigen::VectorXd residuals(const Eigen::VectorXd& theta) const {
    const Vec3 delta = theta.head<3>();
    std::vector<double> raw(points_.size());
    std::vector<std::complex<double>> z(samples_, 0.0);
    for (size_t i = 0; i < points_.size(); ++i) {
      const CalPoint& p = points_[i];
      const Vec3 centre = p.antenna_m + p.orientation * delta;
      double az, el;
      direction_in_frame(centre, p.orientation, tag_[p.sample], az, el);
      const auto b = pattern_basis(az, el);
      double pattern = 0.0;
      for (int t = 0; t < kPatternTerms; ++t) pattern += theta[layout_.pattern(t)] * b[t];
      const double c = p.carrier > 0 ? theta[layout_.carrier(p.carrier)] : 0.0;
      raw[i] = p.phase_rad - fold_ * c - p.k_rad_m * (tag_[p.sample] - centre).norm() - fold_ * pattern;
      z[p.sample] += p.weight * std::polar(1.0, raw[i]);
    }
    Eigen::VectorXd r(points_.size());
    for (size_t i = 0; i < points_.size(); ++i)
      r[i] = std::sqrt(points_[i].weight) * wrap_to_pi(raw[i] - std::arg(z[points_[i].sample]));
    return r;
  }
  std::vector<Vec3> tag_;
  const std::vector<CalPoint>& points() const { return points_; }

 private:
  std::vector<CalPoint> points_;
  int samples_;
  Layout layout_;
  double fold_;
};

}  // namespace

AntennaCalibration calibrate_antenna(const std::vector<CalibrationSample>& samples, const std::string& antenna,
                                     const CalibrationOptions& options) {
  AntennaCalibration out;
  out.antenna = antenna;
  // Carriers present (1 kHz bins), ascending.
  std::vector<double> freqs;
  for (const CalibrationSample& s : samples)
    for (const ReadGroup& g : s.reads.groups)
      if (g.antenna == antenna && !g.reads.empty() &&
          std::none_of(freqs.begin(), freqs.end(), [&](double f) { return std::abs(f - g.frequency_hz) < 1e3; }))
        freqs.push_back(g.frequency_hz);
  std::sort(freqs.begin(), freqs.end());
  if (freqs.empty()) throw InputError("calibration: no reads of antenna '" + antenna + "'");
  Layout layout;
  layout.carriers = static_cast<int>(freqs.size());
  const double fold = options.fold_pi ? 2.0 : 1.0;

  // Stop means per sample via the joint model (no calibration applied).
  std::vector<CalPoint> points;
  std::vector<Vec3> tags;
  JointModelOptions mo;
  mo.stop_tolerance_m = options.stop_tolerance_m;
  mo.read_sigma_rad = options.read_sigma_rad;
  mo.floor_sigma_rad = options.floor_sigma_rad;
  mo.fold_pi = options.fold_pi;
  for (const CalibrationSample& s : samples) {
    TagReads mine;
    mine.tag = s.reads.tag;
    for (const ReadGroup& g : s.reads.groups)
      if (g.antenna == antenna) mine.groups.push_back(g);
    if (mine.read_count() == 0) continue;
    const JointModel m(mine, mo, false, 0.0);
    const int sample = static_cast<int>(tags.size());
    tags.push_back(s.tag_m);
    for (const JointPoint& p : m.points()) {
      const double f = p.k_rad_m / fold * kSpeedOfLight_m_s / (4.0 * kPi);
      int carrier = 0;
      for (size_t c = 0; c < freqs.size(); ++c)
        if (std::abs(freqs[c] - f) < 1e3) carrier = static_cast<int>(c);
      points.push_back({p.antenna_m, p.orientation, p.k_rad_m, p.phase_rad, p.weight, carrier, sample});
    }
    out.reads_used += m.reads();
  }
  out.tags_used = static_cast<int>(tags.size());
  if (tags.size() < 2) throw InputError("calibration: antenna '" + antenna + "' needs reads of at least 2 tags with a known position");

  CalProblem problem(points, static_cast<int>(tags.size()), layout, fold);
  problem.tag_ = tags;
  const int P = layout.size();
  Eigen::VectorXd theta = Eigen::VectorXd::Zero(P);
  // Free parameters and the prior precision of each.
  std::vector<int> free_params;
  Eigen::VectorXd prior = Eigen::VectorXd::Zero(P);
  for (int a = 0; a < 3; ++a) {
    if (options.planar && a == 2) continue;
    free_params.push_back(a);
    prior[a] = 1.0 / std::pow(options.prior_offset_sd_m, 2);
  }
  for (int f = 1; f < layout.carriers; ++f) free_params.push_back(layout.carrier(f));
  if (options.fit_pattern)
    for (int t = 0; t < kPatternTerms; ++t) {
      if (options.planar && t != 0 && t != 2) continue;  // az, az² only
      free_params.push_back(layout.pattern(t));
      prior[layout.pattern(t)] = 1.0 / std::pow(options.prior_pattern_sd_rad, 2);
    }
  // Carrier offsets start from the per-sample coherent angles: c_f = arg Σ_s e^{j(θ_{s,f} − θ_{s,0})}.
  {
    std::vector<std::vector<std::complex<double>>> z(tags.size(), std::vector<std::complex<double>>(layout.carriers, 0.0));
    for (const CalPoint& p : points)
      z[p.sample][p.carrier] += p.weight * std::polar(1.0, p.phase_rad - p.k_rad_m * (tags[p.sample] - p.antenna_m).norm());
    for (int f = 1; f < layout.carriers; ++f) {
      std::complex<double> acc = 0.0;
      for (size_t s = 0; s < tags.size(); ++s)
        if (std::abs(z[s][f]) > 0.0 && std::abs(z[s][0]) > 0.0) acc += z[s][f] / std::abs(z[s][f]) * std::conj(z[s][0]) / std::abs(z[s][0]);
      theta[layout.carrier(f)] = std::abs(acc) > 0.0 ? std::arg(acc) / fold : 0.0;
    }
  }
  const int nf = static_cast<int>(free_params.size());
  auto jacobian = [&](const Eigen::VectorXd& th, const Eigen::VectorXd& r0) {
    Eigen::MatrixXd J(r0.size(), nf);
    for (int c = 0; c < nf; ++c) {
      const double h = free_params[c] < 3 ? 1e-6 : 1e-5;
      Eigen::VectorXd t2 = th;
      t2[free_params[c]] += h;
      const Eigen::VectorXd r1 = problem.residuals(t2);
      for (int i = 0; i < r0.size(); ++i) {
        const double sw = std::sqrt(problem.points()[i].weight);
        J(i, c) = sw * wrap_to_pi((r1[i] - r0[i]) / sw) / h;
      }
    }
    return J;
  };
  auto objective = [&](const Eigen::VectorXd& th, const Eigen::VectorXd& r) {
    double f = r.squaredNorm();
    for (int c : free_params) f += prior[c] * th[c] * th[c];
    return f;
  };
  Eigen::VectorXd r = problem.residuals(theta);
  double f = objective(theta, r);
  double mu = -1.0;
  Eigen::MatrixXd J = jacobian(theta, r);
  for (int it = 0; it < options.max_iterations; ++it) {
    Eigen::MatrixXd A = J.transpose() * J;  // (normal equations of the weighted residuals + prior)
    Eigen::VectorXd g = J.transpose() * r;
    for (int c = 0; c < nf; ++c) A(c, c) += prior[free_params[c]], g[c] += prior[free_params[c]] * theta[free_params[c]];
    // Nearly linear near the truth (δ small, pattern and offsets linear): start close to Gauss–Newton.
    if (mu < 0.0) mu = 1e-6;
    Eigen::MatrixXd Ad = A;
    Ad.diagonal() += mu * A.diagonal();
    Eigen::VectorXd step = Ad.ldlt().solve(-g);
    // Trust region: the wrapped cost has other basins (a cycle per λ/2 of offset), so no step may move the
    // offset by more than 1 cm or a phase parameter by more than 0.3 rad.
    double scale = 1.0;
    for (int c = 0; c < nf; ++c)
      scale = std::min(scale, (free_params[c] < 3 ? 0.01 : 0.3) / std::max(std::abs(step[c]), 1e-300));
    step *= scale;
    Eigen::VectorXd t2 = theta;
    for (int c = 0; c < nf; ++c) t2[free_params[c]] += step[c];
    const Eigen::VectorXd r2 = problem.residuals(t2);
    const double f2 = objective(t2, r2);
    if (f2 < f) {
      const bool small = scale == 1.0 && (f - f2) < 1e-5 * f;
      theta = t2, r = r2, f = f2;
      J = jacobian(theta, r);
      mu = std::max(mu / 10.0, 1e-9);
      if (small) break;
    } else {
      mu *= 10.0;
      if (mu > 1e8) break;
    }
  }
  // Uncertainty.
  Eigen::MatrixXd A = J.transpose() * J;
  for (int c = 0; c < nf; ++c) A(c, c) += prior[free_params[c]];
  const int n = static_cast<int>(r.size());
  const double s2 = std::max(1.0, r.squaredNorm() / std::max(1, n - nf - out.tags_used));
  double num = 0.0, den = 0.0;
  for (int i = 0; i < n; ++i) {
    den += r[i] * r[i];
    if (i > 0 && problem.points()[i].sample == problem.points()[i - 1].sample) num += r[i] * r[i - 1];
  }
  const double r1 = den > 0.0 ? std::clamp(num / den, 0.0, 0.95) : 0.0;
  const Eigen::MatrixXd cov = s2 * (1.0 + r1) / (1.0 - r1) * A.inverse();
  Eigen::VectorXd sd = Eigen::VectorXd::Zero(P);
  for (int c = 0; c < nf; ++c) sd[free_params[c]] = std::sqrt(std::max(0.0, cov(c, c)));
  double e2 = 0.0;
  for (int i = 0; i < n; ++i) e2 += r[i] * r[i] / problem.points()[i].weight;
  out.residual_rms_rad = std::sqrt(e2 / std::max(1, n)) / fold;
  out.phase_centre_offset_m = theta.head<3>();
  out.phase_centre_offset_sd_m = sd.head<3>();
  out.frequencies_hz = freqs;
  out.carrier_offsets_rad.assign(freqs.size(), 0.0);
  out.carrier_offsets_sd_rad.assign(freqs.size(), 0.0);
  for (int fi = 1; fi < layout.carriers; ++fi) {
    out.carrier_offsets_rad[fi] = wrap_to_pi(theta[layout.carrier(fi)]);
    out.carrier_offsets_sd_rad[fi] = sd[layout.carrier(fi)];
  }
  for (int t = 0; t < kPatternTerms; ++t) {
    out.pattern_rad[t] = theta[layout.pattern(t)];
    out.pattern_sd_rad[t] = sd[layout.pattern(t)];
  }
  // The geometry block of the covariance (offset, pattern), fixed parameters at 0.
  auto geometry_index = [&](int param) {
    if (param < 3) return param;
    for (int t = 0; t < kPatternTerms; ++t)
      if (param == layout.pattern(t)) return 3 + t;
    return -1;
  };
  for (int a = 0; a < nf; ++a)
    for (int b = 0; b < nf; ++b) {
      const int ga = geometry_index(free_params[a]), gb = geometry_index(free_params[b]);
      if (ga >= 0 && gb >= 0) out.geometry_covariance(ga, gb) = 0.5 * (cov(a, b) + cov(b, a));
    }
  return out;
}

}  // namespace rfidray::loc
