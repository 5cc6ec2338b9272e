#include "localization/hyperbola.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>

#include "core/units.h"

namespace rfidray::loc {

double residual(const Hyperbola& h, const Vec3& x) {
  return (x - h.f2).norm() - (x - h.f1).norm() - h.delta_m;
}

Vec3 gradient(const Hyperbola& h, const Vec3& x) {
  const Vec3 d2 = x - h.f2, d1 = x - h.f1;
  const double n2 = d2.norm(), n1 = d1.norm();
  Vec3 g = Vec3::Zero();
  if (n2 > 0.0) g += d2 / n2;
  if (n1 > 0.0) g -= d1 / n1;
  return g;
}

namespace {
// The section's constants along rays from F1 in the plane z = height_m (see point_on_ray).
struct RayQuadratic {
  RayQuadratic(const Hyperbola& h, double height_m) : f1(h.f1), height_m(height_m), delta((h.f2 - h.f1).head<2>()) {
    const double c1 = height_m - h.f1.z(), c2 = height_m - h.f2.z();
    D = h.delta_m;
    K = delta.squaredNorm() + c2 * c2 - c1 * c1 - D * D;
    c = K * K - 4.0 * D * D * c1 * c1;
  }
  // Both roots ρ (slot 0: −√, slot 1: +√) on the ray of direction e = (cos ψ, sin ψ); valid[slot] says which
  // lie on the conic's sheet in front of F1.
  void points(const Eigen::Vector2d& e, Vec3 out[2], bool valid[2]) const {
    valid[0] = valid[1] = false;
    const double ed = e.dot(delta);
    const double a = 4.0 * (ed * ed - D * D);
    const double b = -4.0 * K * ed;
    double rho[2];
    int slots = 2;
    if (std::abs(a) < 1e-14 * (std::abs(b) + std::abs(c) + 1e-300)) {
      if (b == 0.0) return;
      rho[0] = -c / b;
      slots = 1;
    } else {
      double disc = b * b - 4.0 * a * c;
      if (disc < 0.0) {
        if (disc > -1e-12 * b * b) disc = 0.0;  // tangent ray: keep the double root
        else return;
      }
      const double s = std::sqrt(disc);
      rho[0] = (-b - s) / (2.0 * a), rho[1] = (-b + s) / (2.0 * a);
    }
    for (int slot = 0; slot < slots; ++slot) {
      const double r = rho[slot];
      if (!(r >= 0.0) || !std::isfinite(r)) continue;
      // Sheet condition: Δ (K − 2ρ e·δ) ≥ 0 (tolerance: the squaring's rounding).
      const double side = K - 2.0 * r * ed;
      if (D * side < -1e-9 * (std::abs(K) + 1.0)) continue;
      out[slot] = Vec3(f1.x() + r * e.x(), f1.y() + r * e.y(), height_m);
      valid[slot] = true;
    }
  }
  Vec3 f1;
  double height_m;
  Eigen::Vector2d delta;
  double D, K, c;
};
}  // namespace

bool point_on_ray(const Hyperbola& h, double height_m, double psi_rad, int slot, Vec3& out) {
  Vec3 p[2];
  bool valid[2];
  RayQuadratic(h, height_m).points(Eigen::Vector2d(std::cos(psi_rad), std::sin(psi_rad)), p, valid);
  if (valid[slot]) out = p[slot];
  return valid[slot];
}

PlaneSection sample_section(const Hyperbola& h, double height_m, int rays, double max_range_m) {
  PlaneSection s;
  sample_section(h, height_m, rays, max_range_m, s);
  return s;
}

void sample_section(const Hyperbola& h, double height_m, int rays, double max_range_m, PlaneSection& s) {
  s.rays = rays;
  s.height_m = height_m;
  s.f1 = h.f1;
  s.points.resize(2 * rays);
  s.packed.assign(2 * rays, -1);
  s.sample_of.clear();
  s.next_is_ray_after.clear();
  s.x_m.clear(), s.y_m.clear(), s.r1_m.clear(), s.chord_sum_m.clear();
  s.scale_m = 0.0;
  thread_local std::vector<char> valid;
  valid.assign(2 * rays, 0);
  // The ray directions, shared by every section of this many rays (the same cos/sin values as computed here).
  thread_local std::vector<Eigen::Vector2d> directions;
  if (static_cast<int>(directions.size()) != rays) {
    directions.resize(rays);
    for (int i = 0; i < rays; ++i) {
      const double psi = kTwoPi * i / rays;
      directions[i] = Eigen::Vector2d(std::cos(psi), std::sin(psi));
    }
  }
  const RayQuadratic quadratic(h, height_m);
  for (int i = 0; i < rays; ++i) {
    Vec3 p[2];
    bool on[2];
    quadratic.points(directions[i], p, on);
    for (int slot = 0; slot < 2; ++slot)
      if (on[slot] && (p[slot] - h.f2).norm() <= max_range_m) {
        s.points[2 * i + slot] = p[slot];
        valid[2 * i + slot] = 1;
      }
  }
  const double c1 = height_m - h.f1.z();
  for (int slot = 0; slot < 2; ++slot)
    for (int i = 0; i < rays; ++i) {
      const int a = 2 * i + slot;
      if (!valid[a]) continue;
      const Vec3& p = s.points[a];
      s.packed[a] = static_cast<int>(s.x_m.size());
      s.sample_of.push_back(a);
      s.next_is_ray_after.push_back(i + 1 < rays && valid[a + 2]);
      // (sqrt of the sum of squares, not hypot: a few times cheaper; its rounding is far inside the margin)
      double chord_sum = 0.0;
      if (!s.x_m.empty()) {
        const double du = p.x() - s.x_m.back(), dv = p.y() - s.y_m.back();
        chord_sum = s.chord_sum_m.back() + std::sqrt(du * du + dv * dv);
      }
      s.chord_sum_m.push_back(chord_sum);
      s.scale_m = std::max({s.scale_m, std::abs(p.x()), std::abs(p.y()), std::abs(p.z())});
      s.x_m.push_back(p.x()), s.y_m.push_back(p.y());
      // The same expression intersect_in_plane evaluates for another conic with this F1 (bitwise equal).
      s.r1_m.push_back(std::sqrt((p.x() - h.f1.x()) * (p.x() - h.f1.x()) + (p.y() - h.f1.y()) * (p.y() - h.f1.y()) +
                                 c1 * c1));
    }
}

namespace {

// Newton on the two loci in the plane (unknowns x, y).
bool polish_2d(const Hyperbola& h1, const Hyperbola& h2, Vec3& x) {
  for (int it = 0; it < 20; ++it) {
    const Eigen::Vector2d r(residual(h1, x), residual(h2, x));
    if (r.lpNorm<Eigen::Infinity>() < 1e-12) return true;
    Eigen::Matrix2d J;
    J.row(0) = gradient(h1, x).head<2>().transpose();
    J.row(1) = gradient(h2, x).head<2>().transpose();
    if (std::abs(J.determinant()) < 1e-14) break;
    const Eigen::Vector2d step = J.partialPivLu().solve(-r);
    x.head<2>() += step;
    if (step.norm() < 1e-13) break;
  }
  return std::abs(residual(h1, x)) < 1e-7 && std::abs(residual(h2, x)) < 1e-7;
}

}  // namespace

std::vector<Vec3> intersect_in_plane(const Hyperbola& h1, const PlaneSection& s1, const Hyperbola& h2) {
  std::vector<Vec3> out;
  intersect_in_plane(h1, s1, h2, out);
  return out;
}

void intersect_in_plane(const Hyperbola& h1, const PlaneSection& s1, const Hyperbola& h2, std::vector<Vec3>& out) {
  // 32 and 8: the fewest instructions of the sizes tried on bench/localize_speed's stage (callgrind, 1 000
  // reads, 3 repeats: 1/1 357.6 M, 8/8 283.8 M, 16/4 280.0 M, 32/8 278.7 M, 64/8 278.9 M, 128/16 281.1 M).
  intersect_in_plane(h1, s1, h2, out, 32, 8);
}

void intersect_in_plane(const Hyperbola& h1, const PlaneSection& s1, const Hyperbola& h2, std::vector<Vec3>& out,
                        int coarse_block, int fine_block) {
  out.clear();
  const int n = s1.rays;
  // h2's residual f = |p − F2| − |p − F1| − δ at the valid samples of the section (the bulk of the method's
  // time: every pair of conics). Conics of one unwrapped segment share F1 (its first antenna position), and
  // then the distance to it is the section's own (one square root per sample instead of two).
  // f is 2-Lipschitz (each distance is 1-Lipschitz), so |f(p_j) − f(p_k)| ≤ 2|p_j − p_k| ≤ 2 (C_j − C_k)
  // with C the section's chord sums. A block of samples k … e whose end values have one sign and
  // |f_k| + |f_e| > 2 (C_e − C_k) + margin has that sign throughout (the two bounds from its ends meet above
  // zero), so none of its neighbour pairs brackets a crossing and its inner samples are not evaluated.
  // Every value that is evaluated is the same expression whatever the block sizes, so the brackets, their end
  // values and hence the points are bitwise those of evaluating every sample (blocks of 1). The margin covers the rounding of f and
  // of C (a few ulps of the coordinates' size; here 1e-9 of it plus 1 µm).
  // (Into storage kept per thread at its largest size.)
  thread_local std::vector<double> f_storage;
  const double c2 = s1.height_m - h2.f2.z(), c1 = s1.height_m - h2.f1.z();
  const double c2c2 = c2 * c2, c1c1 = c1 * c1;
  const Eigen::Index m = static_cast<Eigen::Index>(s1.x_m.size());
  if (f_storage.size() < static_cast<size_t>(m)) f_storage.resize(m);
  double* const f = f_storage.data();
  const double* const x = s1.x_m.data();
  const double* const y = s1.y_m.data();
  const double* const r1 = s1.r1_m.data();
  const double* const chord = s1.chord_sum_m.data();
  const bool shared_f1 = h2.f1 == s1.f1;
  const double f2x = h2.f2.x(), f2y = h2.f2.y(), f1x = h2.f1.x(), f1y = h2.f1.y(), delta = h2.delta_m;
  auto value = [&](Eigen::Index k) {
    const double d2 = std::sqrt((x[k] - f2x) * (x[k] - f2x) + (y[k] - f2y) * (y[k] - f2y) + c2c2);
    if (shared_f1) return d2 - r1[k] - delta;
    return d2 - std::sqrt((x[k] - f1x) * (x[k] - f1x) + (y[k] - f1y) * (y[k] - f1y) + c1c1) - delta;
  };
  const double scale = std::max({s1.scale_m, h2.f1.cwiseAbs().maxCoeff(), h2.f2.cwiseAbs().maxCoeff(),
                                 std::abs(delta), std::abs(s1.height_m)});
  const double margin = 1e-6 + 1e-9 * scale;
  // Sign changes between neighbouring rays of a slot (found in the blocks evaluated in full: a proven block
  // has none), then the track's wrap from the last ray to the first; refined in the order of the first sample
  // (ray, then slot), which fixes the order of the points.
  thread_local std::vector<int> brackets;
  brackets.clear();
  // Blocks of coarse samples; a block that cannot be proven is split into blocks of fine, and a fine block
  // that cannot be proven is evaluated in full.
  const Eigen::Index coarse = std::max(1, coarse_block), fine = std::clamp<Eigen::Index>(fine_block, 1, coarse);
  auto proven = [&](Eigen::Index k, Eigen::Index e) {
    return (f[k] > 0.0) == (f[e] > 0.0) && std::abs(f[k]) + std::abs(f[e]) > 2.0 * (chord[e] - chord[k]) + margin;
  };
  if (m > 0) f[0] = value(0);
  for (Eigen::Index k = 0; k + 1 < m; k += coarse) {
    const Eigen::Index e = std::min(k + coarse, m - 1);
    f[e] = value(e);
    if (proven(k, e)) continue;
    for (Eigen::Index k2 = k; k2 < e; k2 += fine) {
      const Eigen::Index e2 = std::min(k2 + fine, e);
      if (e2 < e) f[e2] = value(e2);
      if (proven(k2, e2)) continue;
      for (Eigen::Index j = k2 + 1; j < e2; ++j) f[j] = value(j);
      for (Eigen::Index j = k2; j < e2; ++j)
        if (s1.next_is_ray_after[j] && (f[j] > 0.0) != (f[j + 1] > 0.0)) brackets.push_back(s1.sample_of[j]);
    }
  }
  for (int slot = 0; slot < 2; ++slot) {
    const int pa = s1.packed[2 * (n - 1) + slot], pb = s1.packed[slot];
    if (pa < 0 || pb < 0) continue;
    f[pa] = value(pa), f[pb] = value(pb);
    if ((f[pa] > 0.0) != (f[pb] > 0.0)) brackets.push_back(2 * (n - 1) + slot);
  }
  std::sort(brackets.begin(), brackets.end());
  const double dpsi = kTwoPi / n;
  const RayQuadratic quadratic(h1, s1.height_m);
  for (const int a : brackets) {
    const int i = a / 2, slot = a % 2;
    const int b = 2 * ((i + 1) % n) + slot;
    const int pa = s1.packed[a], pb = s1.packed[b];
    // Far from the foci the section is nearly radial from F1, so one ray step may span metres of it:
    // a bracketing search on ψ is still valid along the continuous root track; a bracket across a track
    // break (slot swap) converges to the break and is rejected by the polish below. The Illinois variant
    // of regula falsi (Dowell & Jarratt 1971) keeps the bracket and converges superlinearly: ~6 ray
    // evaluations to 1e-12 instead of bisection's 40; on a break it degrades to bracket shrinking.
    double lo = kTwoPi * i / n, hi = lo + dpsi, flo = f[pa], fhi = f[pb];
    Vec3 p = s1.points[a];
    bool ok = true;
    int kept_side = 0;
    for (int it = 0; it < 40 && hi - lo > 1e-15; ++it) {
      double mid = (lo * fhi - hi * flo) / (fhi - flo);
      if (!(mid > lo && mid < hi)) mid = 0.5 * (lo + hi);
      Vec3 on_ray[2];
      bool valid[2];
      quadratic.points(Eigen::Vector2d(std::cos(mid), std::sin(mid)), on_ray, valid);
      if (!valid[slot]) {
        ok = false;
        break;
      }
      const Vec3& pm = on_ray[slot];
      const double fm = residual(h2, pm);
      p = pm;
      if (std::abs(fm) < 1e-13) break;
      if ((fm > 0.0) == (flo > 0.0)) {
        lo = mid, flo = fm;
        if (kept_side == -1) fhi *= 0.5;  // the same end kept twice: halve its value (Illinois)
        kept_side = -1;
      } else {
        hi = mid, fhi = fm;
        if (kept_side == 1) flo *= 0.5;
        kept_side = 1;
      }
    }
    if (!ok) continue;
    if (!polish_2d(h1, h2, p)) continue;
    bool duplicate = false;
    for (const Vec3& q : out) duplicate |= (q - p).norm() < 1e-6;
    if (!duplicate) out.push_back(p);
  }
}

bool intersect_3d(const Hyperbola& a, const Hyperbola& b, const Hyperbola& c, const Vec3& seed, Vec3& out) {
  Vec3 x = seed;
  for (int it = 0; it < 30; ++it) {
    const Eigen::Vector3d r(residual(a, x), residual(b, x), residual(c, x));
    if (r.lpNorm<Eigen::Infinity>() < 1e-12) break;
    Eigen::Matrix3d J;
    J.row(0) = gradient(a, x).transpose();
    J.row(1) = gradient(b, x).transpose();
    J.row(2) = gradient(c, x).transpose();
    const Eigen::Vector3d step = J.colPivHouseholderQr().solve(-r);
    if (!step.allFinite()) return false;
    // Damped: never jump more than 1 m per iteration (keeps Newton on the local sheet).
    x += step.norm() > 1.0 ? Vec3(step / step.norm()) : Vec3(step);
    if (step.norm() < 1e-13) break;
  }
  out = x;
  return std::abs(residual(a, x)) < 1e-7 && std::abs(residual(b, x)) < 1e-7 && std::abs(residual(c, x)) < 1e-7;
}

namespace {
// The square case at a fixed size (the common ones: two conics in the plane, three in space): the same
// decomposition as the general case below, without its run-time sizes (bitwise the same qualities on every
// real and simulated set tried).
template <int N>
double square_quality(const Vec3* gradients) {
  Eigen::Matrix<double, N, N> J;
  for (int i = 0; i < N; ++i) J.row(i) = gradients[i].head<N>().transpose();
  const Eigen::Matrix<double, N, N> A = J.transpose() * J;
  Eigen::FullPivLU<Eigen::Matrix<double, N, N>> lu(A);
  // Eigen's default threshold (ε · size), set explicitly: gcc 12 cannot see that the unset one is never read.
  lu.setThreshold(std::numeric_limits<double>::epsilon() * N);
  if (!lu.isInvertible()) return 0.0;
  const double tr = lu.inverse().trace();
  return tr > 0.0 ? 1.0 / std::sqrt(tr) : 0.0;
}
}  // namespace

double intersection_quality(const Vec3* gradients, int count, bool planar) {
  if (planar && count == 2) return square_quality<2>(gradients);
  if (!planar && count == 3) return square_quality<3>(gradients);
  const int dim = planar ? 2 : 3;
  using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, 3, 3>;  // on the stack
  Small J(count, dim);
  for (int i = 0; i < count; ++i) J.row(i) = gradients[i].head(dim).transpose();
  const Small A = J.transpose() * J;
  Eigen::FullPivLU<Small> lu(A);
  if (!lu.isInvertible()) return 0.0;
  const double tr = lu.inverse().trace();
  return tr > 0.0 ? 1.0 / std::sqrt(tr) : 0.0;
}

}  // namespace rfidray::loc
