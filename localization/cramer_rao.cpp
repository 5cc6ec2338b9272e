#include "localization/cramer_rao.h"

#include <Eigen/Dense>
#include <cmath>

#include "core/units.h"

namespace rfidray::localization {

void PhaseFisher::add(const PhaseObservation& o) {
  if (!(o.weight > 0.0) || !(o.sigma_rad > 0.0) || !(o.wavelength_m > 0.0)) return;
  const Vec3 d = tag_ - o.antenna_m;
  const double r = d.norm();
  if (!(r > 0.0)) return;
  const Vec3 g = (4.0 * kPi / o.wavelength_m) * d / r;  // ∂φ/∂θ
  const double w = o.weight / (o.sigma_rad * o.sigma_rad);
  auto it = groups_.begin();
  while (it != groups_.end() && it->id < o.offset_group) ++it;
  if (it == groups_.end() || it->id != o.offset_group) it = groups_.insert(it, Group{o.offset_group});
  it->weight += w;
  const Vec3 delta = g - it->mean;
  it->mean += (w / it->weight) * delta;
  it->scatter += w * delta * (g - it->mean).transpose();
}

Eigen::Matrix3d PhaseFisher::information() const {
  Eigen::Matrix3d s = Eigen::Matrix3d::Zero();
  for (const Group& g : groups_) s += g.scatter;
  return 0.5 * (s + s.transpose());  // symmetric up to rounding
}

std::optional<double> PhaseFisher::bound_m(bool height_known) const {
  return position_bound_m(information(), height_known);
}

namespace {

template <int N>
std::optional<double> block_bound(const Eigen::Matrix<double, N, N>& block) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, N, N>> eig(block, Eigen::EigenvaluesOnly);
  if (eig.info() != Eigen::Success) return std::nullopt;
  const auto ev = eig.eigenvalues();  // ascending
  // Identifiable only when every direction is constrained well above round-off, relative to the strongest.
  if (!(ev(N - 1) > 0.0) || !(ev(0) > 1e-9 * ev(N - 1))) return std::nullopt;
  double trace = 0.0;
  for (int k = 0; k < N; ++k) trace += 1.0 / ev(k);
  const double bound = std::sqrt(trace);
  if (!std::isfinite(bound)) return std::nullopt;
  return bound;
}

}  // namespace

std::optional<double> position_bound_m(const Eigen::Matrix3d& s, bool height_known) {
  if (!s.allFinite()) return std::nullopt;
  return height_known ? block_bound<2>(s.topLeftCorner<2, 2>()) : block_bound<3>(s);
}

std::array<double, 6> pack_information(const Eigen::Matrix3d& s) {
  return {s(0, 0), s(0, 1), s(0, 2), s(1, 1), s(1, 2), s(2, 2)};
}

Eigen::Matrix3d unpack_information(const double* p) {
  Eigen::Matrix3d s;
  s << p[0], p[1], p[2], p[1], p[3], p[4], p[2], p[4], p[5];
  return s;
}

std::optional<double> phase_position_crb_m(const Vec3& tag, std::span<const PhaseObservation> observations,
                                           bool height_known) {
  PhaseFisher f(tag);
  for (const PhaseObservation& o : observations) f.add(o);
  return f.bound_m(height_known);
}

}  // namespace rfidray::localization
