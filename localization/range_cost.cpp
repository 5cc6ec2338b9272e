#include "localization/range_cost.h"

#include "localization/levenberg_marquardt.h"

#include <cmath>
#include <limits>

namespace rfidray::loc {

RangeCost::RangeCost(const PreparedTag& prep, bool fixed_z, double z_m) : prep_(prep), fixed_z_(fixed_z), z_m_(z_m) {
  for (const auto& s : prep.segments) {
    n_ += static_cast<int>(s.range_m.size());
    std::vector<double> x, y, z, reads, means;
    size_t start = 0;
    while (start < s.range_m.size()) {
      size_t end = start + 1;
      while (end < s.range_m.size() && s.antenna_m[end] == s.antenna_m[start]) ++end;
      double mean = 0.0;
      for (size_t k = start; k < end; ++k) mean += s.range_m[k];
      mean /= static_cast<double>(end - start);
      for (size_t k = start; k < end; ++k) within_stop_scatter_m2_ += (s.range_m[k] - mean) * (s.range_m[k] - mean);
      x.push_back(s.antenna_m[start].x()), y.push_back(s.antenna_m[start].y()), z.push_back(s.antenna_m[start].z());
      reads.push_back(static_cast<double>(end - start)), means.push_back(mean);
      start = end;
    }
    const Eigen::Index m = static_cast<Eigen::Index>(x.size());
    using Map = Eigen::Map<const Eigen::ArrayXd>;
    stops_.push_back({Map(x.data(), m), Map(y.data(), m), Map(z.data(), m), Map(reads.data(), m), Map(means.data(), m)});
  }
}

Vec3 RangeCost::to_position(const Eigen::VectorXd& u) const {
  return fixed_z_ ? Vec3(u[0], u[1], z_m_) : Vec3(u[0], u[1], u[2]);
}

Eigen::VectorXd RangeCost::to_unknowns(const Vec3& x) const {
  if (fixed_z_) return Eigen::Vector2d(x.x(), x.y());
  return x;
}

void RangeCost::evaluate(const Vec3& x, Eigen::VectorXd& r, Eigen::MatrixXd* J) const {
  r.resize(n_);
  if (J) J->resize(n_, dof());
  int row = 0;
  for (const RangeSegment& s : prep_.segments) {
    const int m = static_cast<int>(s.range_m.size());
    double mean_e = 0.0;
    Vec3 mean_u = Vec3::Zero();
    for (int k = 0; k < m; ++k) {
      const Vec3 d = x - s.antenna_m[k];
      const double dist = d.norm();
      r[row + k] = s.range_m[k] - dist;
      mean_e += r[row + k];
      if (J) {
        const Vec3 u = dist > 0.0 ? Vec3(d / dist) : Vec3::Zero();
        // ∂e/∂x = −∂D/∂x = −u (before centring)
        for (int c = 0; c < dof(); ++c) (*J)(row + k, c) = -u[c];
        mean_u += u;
      }
    }
    mean_e /= m;
    mean_u /= m;
    for (int k = 0; k < m; ++k) {
      r[row + k] -= mean_e;
      if (J)
        for (int c = 0; c < dof(); ++c) (*J)(row + k, c) += mean_u[c];
    }
    row += m;
  }
}

double RangeCost::ssr(const Vec3& x) const {
  // Per segment Σ e² − (Σ e)² / m over its stops, e = m̄_s − D_s (see stops_).
  double total = within_stop_scatter_m2_;
  for (size_t g = 0; g < stops_.size(); ++g) {
    const Stops& st = stops_[g];
    // In packets: the square roots are most of the cost (per-thread buffer: the grid calls this in parallel).
    thread_local Eigen::ArrayXd e;
    e = st.mean_range_m - ((x.x() - st.x_m).square() + (x.y() - st.y_m).square() + (x.z() - st.z_m).square()).sqrt();
    const double sum = (st.reads * e).sum(), sum2 = (st.reads * e.square()).sum();
    total += sum2 - sum * sum / static_cast<double>(prep_.segments[g].range_m.size());
  }
  return std::max(total, 0.0);
}

double RangeCost::offset_m(const Vec3& x, int segment) const {
  const RangeSegment& s = prep_.segments[segment];
  double sum = 0.0;
  for (size_t k = 0; k < s.range_m.size(); ++k) sum += s.range_m[k] - (x - s.antenna_m[k]).norm();
  return sum / static_cast<double>(s.range_m.size());
}

double predicted_std_m(const RangeCost& cost, const Vec3& x, double sigma_m) {
  Eigen::VectorXd r;
  Eigen::MatrixXd J;
  cost.evaluate(x, r, &J);
  const Eigen::MatrixXd A = J.transpose() * J;
  Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
  if (!lu.isInvertible()) return std::numeric_limits<double>::infinity();
  const double tr = lu.inverse().trace();
  return tr > 0.0 ? sigma_m * std::sqrt(tr) : std::numeric_limits<double>::infinity();
}

LmResult levenberg_marquardt(const RangeCost& cost, const Vec3& start, int max_iterations) {
  const LmSolution sol = levenberg_marquardt_core(
      cost.to_unknowns(start),
      [&](const Eigen::VectorXd& u, Eigen::VectorXd& r, Eigen::MatrixXd* J) { cost.evaluate(cost.to_position(u), r, J); },
      max_iterations, LmTolerances{});
  LmResult out;
  out.position = cost.to_position(sol.unknowns);
  out.ssr = sol.cost;
  out.iterations = sol.iterations;
  out.converged = sol.converged && out.position.allFinite();
  return out;
}

}  // namespace rfidray::loc
