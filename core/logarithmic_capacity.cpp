#include "core/logarithmic_capacity.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/LU>

#include "core/error.h"
#include "core/units.h"

namespace rfidray {
namespace {

// ∫ −ln|x − r| dl over the panel from p0 to p1 (unit charge density): with t along the panel from x's foot and v
// x's distance from its line, −½ [F(t1) − F(t0)], F(t) = t ln(t² + v²) − 2t + 2v atan(t/v).
double panel_potential(const Eigen::Vector2d& x, const Eigen::Vector2d& p0, const Eigen::Vector2d& p1) {
  const Eigen::Vector2d d = p1 - p0;
  const double len = d.norm();
  const Eigen::Vector2d u = d / len;
  const Eigen::Vector2d r = x - p0;
  const double along = r.dot(u);
  const double v = std::abs(u.x() * r.y() - u.y() * r.x());
  const auto f = [v](double t) {
    const double q = t * t + v * v;
    const double log_part = q > 0.0 ? t * std::log(q) : 0.0;
    return log_part - 2.0 * t + (v > 0.0 ? 2.0 * v * std::atan(t / v) : 0.0);
  };
  // t runs from −along (at p0) to len − along (at p1), measured from x's foot.
  return -0.5 * (f(len - along) - f(-along));
}

}  // namespace

double logarithmic_capacity_m(std::span<const Eigen::Vector2d> outline, int panels) {
  std::vector<Eigen::Vector2d> pts;
  for (const auto& p : outline) {
    if (!p.allFinite()) throw InputError("logarithmic capacity: a vertex is not finite");
    if (pts.empty() || (p - pts.back()).norm() > 1e-12) pts.push_back(p);
  }
  if (pts.size() > 2 && (pts.front() - pts.back()).norm() <= 1e-12) pts.pop_back();
  if (pts.size() < 2) throw InputError("logarithmic capacity: fewer than 2 distinct vertices");
  // A segment is one side; a polygon is closed.
  const size_t sides = pts.size() == 2 ? 1 : pts.size();
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const auto& p : pts) centre += p;
  centre /= static_cast<double>(pts.size());
  double extent = 0.0;
  for (const auto& p : pts) extent = std::max(extent, (p - centre).norm());
  // Scaled to extent 0.5: the capacity is then below 1 and ln(cap) well away from 0 (cap = 1 makes Q infinite).
  const double scale = 0.5 / extent;
  double perimeter = 0.0;
  for (size_t s = 0; s < sides; ++s) perimeter += (pts[(s + 1) % pts.size()] - pts[s]).norm();
  // Panel ends, each side cut in proportion to its length, graded by cosine spacing towards its corners.
  std::vector<Eigen::Vector2d> a, b;
  for (size_t s = 0; s < sides; ++s) {
    const Eigen::Vector2d p0 = (pts[s] - centre) * scale, p1 = (pts[(s + 1) % pts.size()] - centre) * scale;
    const int n = std::max(sides <= 8 ? 4 : 1, static_cast<int>(std::lround(panels * (pts[(s + 1) % pts.size()] - pts[s]).norm() /
                                                           perimeter)));
    for (int i = 0; i < n; ++i) {
      const double t0 = 0.5 * (1.0 - std::cos(kPi * i / n)), t1 = 0.5 * (1.0 - std::cos(kPi * (i + 1) / n));
      a.push_back(p0 + t0 * (p1 - p0));
      b.push_back(p0 + t1 * (p1 - p0));
    }
  }
  const Eigen::Index m = static_cast<Eigen::Index>(a.size());
  Eigen::MatrixXd g(m, m);
  for (Eigen::Index i = 0; i < m; ++i) {
    const Eigen::Vector2d x = 0.5 * (a[i] + b[i]);
    for (Eigen::Index j = 0; j < m; ++j) g(i, j) = panel_potential(x, a[j], b[j]);
  }
  const Eigen::VectorXd sigma = g.partialPivLu().solve(Eigen::VectorXd::Ones(m));
  double q = 0.0;
  for (Eigen::Index j = 0; j < m; ++j) q += sigma[j] * (b[j] - a[j]).norm();
  return std::exp(-1.0 / q) / scale;
}

}  // namespace rfidray
