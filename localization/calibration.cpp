#include "localization/calibration.h"

#include <Eigen/Dense>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <complex>
#include <map>
#include <sstream>
#include <tuple>

#include "core/error.h"
#include "core/units.h"
#include "localization/allowance.h"
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

// calibrate_antenna without the choice of terms. `uncalibrated`: each sample's error localized without any
// calibration (allowance.h, uncalibrated_errors), computed here when empty and kept for the next call.
AntennaCalibration fit_calibration(const std::vector<CalibrationSample>& samples, const std::string& antenna,
                                   const CalibrationOptions& options, std::vector<double>& uncalibrated) {
  AntennaCalibration out;
  out.antenna = antenna;
  // Carriers present (1 kHz bins), ascending.
  std::vector<double> freqs;
  for (const CalibrationSample& s : samples)
    for (const ReadGroup& g : s.reads.groups)
      if (s.fit_geometry && g.antenna == antenna && !g.reads.empty() &&
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
    if (!s.fit_geometry) continue;
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
  // What the reference geometry cannot determine is held at 0 and said (out.not_fitted).
  std::array<bool, 3> fix_offset{false, false, false};
  std::array<bool, kPatternTerms> fix_pattern{};
  auto note_fixed = [&](const std::string& term, const std::string& why) {
    for (const auto& n : out.not_fitted)
      if (n.term == term) return;
    out.not_fitted.push_back({term, why});
  };
  bool horizontal_plane = options.planar;  // every tag at the antennas' height: the allowance localizes in 2-D
  if (!options.fit_offset) fix_offset = {true, true, true};  // notes: calibrate_antenna's choice of terms
  if (options.planar) {
    const std::string why = "--height-known: antenna and tags in one horizontal plane";
    fix_offset[2] = true, note_fixed("dz", why);
    for (int t : {1, 3, 4}) fix_pattern[t] = true, note_fixed(kPatternTermNames[t], why);
  }
  {
    // Planarity of every antenna position and tag: the smallest singular value of the centred coordinates is
    // √N × the RMS distance to the best-fit plane.
    // Each distinct position once (1 mm): thousands of reads at one stop must not outweigh the tags.
    std::vector<Vec3> all;
    std::map<std::tuple<long, long, long>, bool> seen;
    auto add = [&](const Vec3& v) {
      if (seen.emplace(std::make_tuple(std::lround(v.x() * 1e3), std::lround(v.y() * 1e3), std::lround(v.z() * 1e3)), true).second)
        all.push_back(v);
    };
    for (const CalPoint& p : points) add(p.antenna_m);
    for (const Vec3& t : tags) add(t);
    Vec3 mean = Vec3::Zero();
    for (const Vec3& v : all) mean += v / static_cast<double>(all.size());
    Eigen::MatrixXd X(all.size(), 3);
    for (size_t i = 0; i < all.size(); ++i) X.row(i) = (all[i] - mean).transpose();
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(X, Eigen::ComputeThinV);
    const double rms_out_m = svd.singularValues()[2] / std::sqrt(static_cast<double>(all.size()));
    // Not a line: the RMS distance from the best-fit line is well above the plane's tolerance.
    const bool spans_plane = svd.singularValues()[1] / std::sqrt(static_cast<double>(all.size())) > 5.0 * options.planar_tolerance_m;
    if (rms_out_m < options.planar_tolerance_m && spans_plane) {
      const Vec3 normal = svd.matrixV().col(2);
      horizontal_plane = horizontal_plane || std::abs(normal.z()) > std::cos(10.0 * kPi / 180.0);
      // The normal in each antenna frame: one axis for every point, or the offset mixes axes (left to the
      // Jacobian test below).
      Vec3 frame_normal = points.front().orientation.conjugate() * normal;
      bool same = true;
      for (const CalPoint& p : points)
        same = same && std::abs((p.orientation.conjugate() * normal).dot(frame_normal)) > std::cos(5.0 * kPi / 180.0);
      int axis = 0;
      frame_normal.cwiseAbs().maxCoeff(&axis);
      if (same && std::abs(frame_normal[axis]) > std::cos(10.0 * kPi / 180.0)) {
        std::ostringstream why;
        why << "reference tags and antenna positions lie in one plane (RMS " << rms_out_m * 100.0
            << " cm out of it, limit " << options.planar_tolerance_m * 100.0
            << " cm): the offset normal to it changes every range only to second order and not by its sign";
        const char* axis_name[] = {"dx", "dy", "dz"};
        if (!fix_offset[axis]) fix_offset[axis] = true, note_fixed(axis_name[axis], why.str());
        if (axis == 2) {
          // The plane holds the antenna's x and y axes: every direction has el = 0.
          std::ostringstream el_why;
          el_why << "every reference direction has elevation 0 (the plane of tags and antenna positions holds the "
                    "antenna's boresight and y axis): the elevation terms have no effect";
          for (int t : {1, 3, 4})
            if (!fix_pattern[t]) fix_pattern[t] = true, note_fixed(kPatternTermNames[t], el_why.str());
        }
      }
    }
  }
  // Free parameters and the prior precision of each.
  std::vector<int> free_params;
  Eigen::VectorXd prior = Eigen::VectorXd::Zero(P);
  Eigen::VectorXd prior_sd = Eigen::VectorXd::Ones(P);
  for (int a = 0; a < 3; ++a) {
    if (fix_offset[a]) continue;
    free_params.push_back(a);
    prior[a] = 1.0 / std::pow(options.prior_offset_sd_m, 2);
    prior_sd[a] = options.prior_offset_sd_m;
  }
  for (int f = 1; f < layout.carriers; ++f) free_params.push_back(layout.carrier(f));
  if (options.fit_pattern)
    for (int t = 0; t < kPatternTerms; ++t) {
      if (fix_pattern[t]) continue;
      free_params.push_back(layout.pattern(t));
      prior[layout.pattern(t)] = 1.0 / std::pow(options.prior_pattern_sd_rad, 2);
      prior_sd[layout.pattern(t)] = options.prior_pattern_sd_rad;
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
  // Over the current free_params (the check below may drop some).
  auto jacobian = [&](const Eigen::VectorXd& th, const Eigen::VectorXd& r0) {
    const int cols = static_cast<int>(free_params.size());
    Eigen::MatrixXd J(r0.size(), cols);
    for (int c = 0; c < cols; ++c) {
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
  // Parameters the reads do not depend on at the start (a Jacobian column, in units of the parameter's prior
  // sd, below min_relative_information of the largest): the data cannot tell them, so they are not fitted.
  {
    const Eigen::VectorXd r0 = problem.residuals(theta);
    const Eigen::MatrixXd J0 = jacobian(theta, r0);
    Eigen::VectorXd info(nf);
    for (int c = 0; c < nf; ++c) info[c] = J0.col(c).norm() * prior_sd[free_params[c]];
    const double largest = info.maxCoeff();
    std::vector<int> kept;
    for (int c = 0; c < nf; ++c) {
      const int g = free_params[c] < 3 ? free_params[c] : -1;
      int t = -1;
      for (int k = 0; k < kPatternTerms; ++k)
        if (free_params[c] == layout.pattern(k)) t = k;
      if ((g >= 0 || t >= 0) && !(info[c] >= options.min_relative_information * largest)) {
        std::ostringstream why;
        why << "the reads do not depend on it (its Jacobian column, scaled by its prior sd, is " << info[c] / largest
            << " of the largest)";
        note_fixed(g >= 0 ? kGeometryTermNames[g] : kPatternTermNames[t], why.str());
        continue;
      }
      kept.push_back(free_params[c]);
    }
    if (static_cast<int>(kept.size()) != nf) {
      for (int c = 0; c < P; ++c)
        if (std::find(kept.begin(), kept.end(), c) == kept.end()) prior[c] = 0.0;
      free_params = kept;
    }
  }
  const int nf_used = static_cast<int>(free_params.size());
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
    for (int c = 0; c < nf_used; ++c) A(c, c) += prior[free_params[c]], g[c] += prior[free_params[c]] * theta[free_params[c]];
    // Nearly linear near the truth (δ small, pattern and offsets linear): start close to Gauss–Newton.
    if (mu < 0.0) mu = 1e-6;
    Eigen::MatrixXd Ad = A;
    Ad.diagonal() += mu * A.diagonal();
    Eigen::VectorXd step = Ad.ldlt().solve(-g);
    // Trust region: the wrapped cost has other basins (a cycle per λ/2 of offset), so no step may move the
    // offset by more than 1 cm or a phase parameter by more than 0.3 rad.
    double scale = 1.0;
    for (int c = 0; c < nf_used; ++c)
      scale = std::min(scale, (free_params[c] < 3 ? 0.01 : 0.3) / std::max(std::abs(step[c]), 1e-300));
    step *= scale;
    Eigen::VectorXd t2 = theta;
    for (int c = 0; c < nf_used; ++c) t2[free_params[c]] += step[c];
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
  for (int c = 0; c < nf_used; ++c) A(c, c) += prior[free_params[c]];
  const int n = static_cast<int>(r.size());
  const double s2 = std::max(1.0, r.squaredNorm() / std::max(1, n - nf_used - out.tags_used));
  double num = 0.0, den = 0.0;
  for (int i = 0; i < n; ++i) {
    den += r[i] * r[i];
    if (i > 0 && problem.points()[i].sample == problem.points()[i - 1].sample) num += r[i] * r[i - 1];
  }
  const double r1 = den > 0.0 ? std::clamp(num / den, 0.0, 0.95) : 0.0;
  const Eigen::MatrixXd cov = s2 * (1.0 + r1) / (1.0 - r1) * A.inverse();
  Eigen::VectorXd sd = Eigen::VectorXd::Zero(P);
  for (int c = 0; c < nf_used; ++c) sd[free_params[c]] = std::sqrt(std::max(0.0, cov(c, c)));
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
  for (int a = 0; a < nf_used; ++a)
    for (int b = 0; b < nf_used; ++b) {
      const int ga = geometry_index(free_params[a]), gb = geometry_index(free_params[b]);
      if (ga >= 0 && gb >= 0) out.geometry_covariance(ga, gb) = 0.5 * (cov(a, b) + cov(b, a));
    }
  // Fitted, but hardly by the data: the posterior sd is nearly the prior's (the prior bounds it).
  for (int c = 0; c < nf_used; ++c) {
    const int g = geometry_index(free_params[c]);
    if (g < 0) continue;
    const double ratio = sd[free_params[c]] / prior_sd[free_params[c]];
    if (ratio > options.prior_bounded_fraction) {
      std::ostringstream why;
      why << "sd " << sd[free_params[c]] << " is " << ratio << " of its prior sd " << prior_sd[free_params[c]]
          << ": the reference tags hardly determine it, the prior N(0, sd^2) bounds it";
      out.prior_bounded.push_back({kGeometryTermNames[g], why.str()});
    }
  }
  // Fitted, but only as a combination with another term (their estimates nearly one line).
  for (int a = 0; a < kGeometryTerms; ++a)
    for (int b = a + 1; b < kGeometryTerms; ++b) {
      const double var = out.geometry_covariance(a, a) * out.geometry_covariance(b, b);
      if (!(var > 0.0)) continue;
      const double correlation = out.geometry_covariance(a, b) / std::sqrt(var);
      if (!(std::abs(correlation) > options.aliased_correlation)) continue;
      std::ostringstream why;
      why << "correlated at " << correlation << ": the reference tags tell only a combination of the two (both "
          << "bend the phase along the aperture alike), so each alone means little; the held-out check says whether "
          << "the pair carries to other runs";
      out.aliased.push_back({std::string(kGeometryTermNames[a]) + "/" + kGeometryTermNames[b], why.str()});
    }
  if (!options.fit_carriers) {
    // Nothing calibrated (CalibrationOptions::fit_carriers): each carrier its own offset, as without a file.
    out.frequencies_hz.clear();
    out.carrier_offsets_rad.clear();
    out.carrier_offsets_sd_rad.clear();
    out.phase_centre_offset_m = out.phase_centre_offset_sd_m = Vec3::Zero();
    out.pattern_rad = out.pattern_sd_rad = {};
    out.geometry_covariance.setZero();
    out.prior_bounded.clear();
    out.aliased.clear();
    out.residual_rms_rad = std::numeric_limits<double>::quiet_NaN();  // no fit
  }
  if (options.measure_allowance || options.held_out_check) {
    CalibrationOptions measured = options;
    measured.planar = horizontal_plane;
    // Each reference localized without calibration once, for both checks (and every model calibrate_antenna tries).
    if (uncalibrated.empty()) uncalibrated = uncalibrated_errors(samples, antenna, measured);
    if (options.measure_allowance) measure_allowance(samples, measured, uncalibrated, out);
    if (options.held_out_check) measure_held_out(samples, measured, uncalibrated, out);
  }
  return out;
}

}  // namespace

size_t model_with_lowest_held_out_error(const std::vector<double>& held_out_median_error_m) {
  size_t chosen = 0;
  for (size_t m = 1; m < held_out_median_error_m.size(); ++m) {
    const double e = held_out_median_error_m[m];
    // An unmeasured model is never chosen over a measured one; an unmeasured richer one gives way to a measured one.
    if (std::isfinite(e) && !(e > held_out_median_error_m[chosen])) chosen = m;
  }
  return chosen;
}

AntennaCalibration calibrate_antenna(const std::vector<CalibrationSample>& samples, const std::string& antenna,
                                     const CalibrationOptions& options) {
  std::vector<double> uncalibrated;
  AntennaCalibration full = fit_calibration(samples, antenna, options, uncalibrated);
  if (!options.select_terms || full.held_out_tags == 0) return full;  // no held-out evidence to choose by
  auto is_free = [&](const char* term) {
    return std::none_of(full.not_fitted.begin(), full.not_fitted.end(), [&](const auto& n) { return n.term == term; });
  };
  std::vector<std::string> pattern_terms, offset_terms;
  if (options.fit_pattern)
    for (const char* t : kPatternTermNames)
      if (is_free(t)) pattern_terms.push_back(t);
  if (options.fit_offset)
    for (int a = 0; a < 3; ++a)
      if (is_free(kGeometryTermNames[a])) offset_terms.push_back(kGeometryTermNames[a]);
  // The nested models, richest first: what `options` fits, then without the pattern, then without the offset too.
  struct Model {
    std::string name;
    CalibrationOptions options;
    AntennaCalibration fitted;  // its held_out_* are the model's cross-validation
  };
  std::vector<Model> models;
  const std::string carriers = full.has_carrier_offsets() ? "carrier offsets" : "(no carrier offsets: one carrier)";
  std::string name = carriers;
  if (!offset_terms.empty()) name += " + phase-centre offset";
  if (!pattern_terms.empty()) name += " + pattern";
  models.push_back({name, options, full});
  CalibrationOptions variant = options;
  variant.measure_allowance = false;  // measured once, on the model kept
  if (!pattern_terms.empty() && !offset_terms.empty()) {
    variant.fit_pattern = false;
    models.push_back({carriers + " + phase-centre offset", variant, fit_calibration(samples, antenna, variant, uncalibrated)});
  }
  if (!pattern_terms.empty() || !offset_terms.empty()) {
    variant.fit_pattern = false, variant.fit_offset = false;
    models.push_back({carriers, variant, fit_calibration(samples, antenna, variant, uncalibrated)});
  }
  std::vector<double> medians;
  for (const Model& m : models) medians.push_back(m.fitted.held_out_median_error_m);
  // Last, nothing: localized without calibration, the held-out tags' error is the uncalibrated one the full
  // model's check measured on the same folds (no fit to cross-validate).
  const bool can_drop_all = full.has_carrier_offsets() || !pattern_terms.empty() || !offset_terms.empty();
  if (can_drop_all) {
    variant.fit_pattern = false, variant.fit_offset = false, variant.fit_carriers = false;
    variant.held_out_check = false;
    models.push_back({"nothing (each carrier its own offset, as without an antenna file)", variant, full});
    medians.push_back(full.held_out_median_error_uncalibrated_m);
  }
  const size_t chosen = model_with_lowest_held_out_error(medians);
  std::vector<AntennaCalibration::HeldOutModel> tried;
  for (size_t m = 0; m < models.size(); ++m)
    tried.push_back({models[m].name, medians[m], m == chosen});
  if (chosen == 0) {
    full.held_out_models = tried;
    return full;
  }
  // Refitted with the allowance measured (the held-out figures are those of the model's own cross-validation).
  CalibrationOptions kept = models[chosen].options;
  kept.measure_allowance = options.measure_allowance;
  kept.held_out_check = false;
  AntennaCalibration out = fit_calibration(samples, antenna, kept, uncalibrated);
  const AntennaCalibration& measured = models[chosen].fitted;
  out.held_out_median_error_m = medians[chosen];
  out.held_out_median_error_uncalibrated_m = measured.held_out_median_error_uncalibrated_m;
  out.held_out_tags = measured.held_out_tags;
  out.held_out_runs = measured.held_out_runs;
  out.held_out_folds = measured.held_out_folds;
  out.held_out_models = tried;
  std::ostringstream why;
  why << "cross-validated over " << full.held_out_runs << " runs in " << full.held_out_folds
      << " folds, the held-out reference tags' median error is " << 1e3 * medians[0] << " mm with " << models[0].name;
  for (size_t m = 1; m <= chosen; ++m) why << ", " << 1e3 * medians[m] << " mm with " << models[m].name;
  why << ": the simpler model localizes the tags of runs it was not fitted on at least as well (what the term fits "
         "in some runs does not carry to the others)";
  if (!kept.fit_carriers) out.carriers_not_fitted = why.str();
  std::vector<std::string> dropped = pattern_terms;
  if (!models[chosen].options.fit_offset) dropped.insert(dropped.end(), offset_terms.begin(), offset_terms.end());
  for (const std::string& t : dropped) out.not_fitted.push_back({t, why.str()});
  return out;
}

}  // namespace rfidray::loc
