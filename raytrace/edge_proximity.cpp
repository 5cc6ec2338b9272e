#include "raytrace/edge_proximity.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rfidray {

uint64_t EdgeProximity::key(int64_t i, int64_t j, int64_t k) {
  // 21 bits per axis (cells of ≥ 2 mm over ±2 km; beyond, cells alias, which costs time, never a wrong answer:
  // every candidate's distance is measured).
  const auto m = [](int64_t v) { return static_cast<uint64_t>(v) & 0x1FFFFFu; };
  return (m(i) << 42) | (m(j) << 21) | m(k);
}

EdgeProximity::EdgeProximity(const std::vector<Edge>& edges, double radius_m) : edges_(edges), radius_m_(radius_m) {
  if (!(std::isfinite(radius_m) && radius_m > 0.0))
    throw std::invalid_argument("EdgeProximity: the radius must be finite and > 0");
  cell_m_ = 2.0 * radius_m;
  for (uint32_t e = 0; e < edges_.size(); ++e) {
    const Edge& edge = edges_[e];
    // An edge beyond the indexable range is never near a query point that passes the same bound.
    if (!edge.start.allFinite() || edge.start.cwiseAbs().maxCoeff() > 1e15 * cell_m_ ||
        !(edge.length_m <= 1e6 * radius_m))
      continue;
    const int samples = 1 + static_cast<int>(std::ceil(edge.length_m / radius_m));
    int64_t last[3] = {INT64_MIN, INT64_MIN, INT64_MIN};
    for (int s = 0; s <= samples; ++s) {
      const Vec3 p = edge.start + (edge.length_m * s / samples) * edge.direction;
      const int64_t c[3] = {static_cast<int64_t>(std::floor(p.x() / cell_m_)),
                            static_cast<int64_t>(std::floor(p.y() / cell_m_)),
                            static_cast<int64_t>(std::floor(p.z() / cell_m_))};
      if (c[0] == last[0] && c[1] == last[1] && c[2] == last[2]) continue;
      std::copy(c, c + 3, last);
      std::vector<uint32_t>& cell = cells_[key(c[0], c[1], c[2])];
      if (cell.empty() || cell.back() != e) cell.push_back(e);
    }
  }
}

std::array<EdgeProximity::Hit, 2> EdgeProximity::nearest_two(const Vec3& point) const {
  std::array<Hit, 2> best{};
  nearest(point, best);
  return best;
}

void EdgeProximity::nearest(const Vec3& point, std::span<Hit> best) const {
  std::fill(best.begin(), best.end(), Hit{});
  if (best.empty()) return;
  // Cell indices must fit an int64 (a point 1e308 away is far from every edge in any case).
  if (!point.allFinite() || point.cwiseAbs().maxCoeff() > 1e15 * cell_m_) return;
  const int64_t ci = static_cast<int64_t>(std::floor(point.x() / cell_m_));
  const int64_t cj = static_cast<int64_t>(std::floor(point.y() / cell_m_));
  const int64_t ck = static_cast<int64_t>(std::floor(point.z() / cell_m_));
  for (int64_t di = -1; di <= 1; ++di)
    for (int64_t dj = -1; dj <= 1; ++dj)
      for (int64_t dk = -1; dk <= 1; ++dk) {
        const auto it = cells_.find(key(ci + di, cj + dj, ck + dk));
        if (it == cells_.end()) continue;
        for (uint32_t e : it->second) {
          // An edge sampled into several cells is measured once.
          if (std::any_of(best.begin(), best.end(), [&](const Hit& h) { return h.edge == e; })) continue;
          const Edge& edge = edges_[e];
          const double z = std::clamp((point - edge.start).dot(edge.direction), 0.0, edge.length_m);
          const double d = (point - (edge.start + z * edge.direction)).norm();
          if (d > radius_m_) continue;
          // Ties go to the lower index, so the answer does not depend on the cells' order.
          const auto before = [&](const Hit& h) {
            return h.edge == kNoEdge || d < h.distance_m || (d == h.distance_m && e < h.edge);
          };
          // Insertion into the sorted list; the last one falls off.
          size_t k = best.size();
          while (k > 0 && before(best[k - 1])) --k;
          if (k == best.size()) continue;
          for (size_t m = best.size() - 1; m > k; --m) best[m] = best[m - 1];
          best[k] = {e, d};
        }
      }
}

void EdgeProximity::edges_near_segment(const Vec3& a, const Vec3& b, double distance_m, std::vector<uint32_t>& out) const {
  out.clear();
  if (!a.allFinite() || !b.allFinite() || !(distance_m >= 0.0) || !std::isfinite(distance_m)) return;
  const double reach = distance_m + 0.5 * radius_m_;
  const Vec3 lo = a.cwiseMin(b).array() - reach, hi = a.cwiseMax(b).array() + reach;
  if (lo.cwiseAbs().maxCoeff() > 1e15 * cell_m_ || hi.cwiseAbs().maxCoeff() > 1e15 * cell_m_) return;
  int64_t c0[3], c1[3];
  double cells = 1.0;
  for (int k = 0; k < 3; ++k) {
    c0[k] = static_cast<int64_t>(std::floor(lo[k] / cell_m_));
    c1[k] = static_cast<int64_t>(std::floor(hi[k] / cell_m_));
    cells *= double(c1[k] - c0[k] + 1);
  }
  if (cells > 1e6) {  // a segment across a huge scene: every edge
    out.resize(edges_.size());
    for (uint32_t e = 0; e < edges_.size(); ++e) out[e] = e;
    return;
  }
  const Vec3 d = b - a;
  const double d2 = d.squaredNorm();
  const double half_diagonal = 0.5 * std::sqrt(3.0) * cell_m_;
  for (int64_t i = c0[0]; i <= c1[0]; ++i)
    for (int64_t j = c0[1]; j <= c1[1]; ++j)
      for (int64_t k = c0[2]; k <= c1[2]; ++k) {
        const Vec3 centre((double(i) + 0.5) * cell_m_, (double(j) + 0.5) * cell_m_, (double(k) + 0.5) * cell_m_);
        const double s = d2 > 0.0 ? std::clamp((centre - a).dot(d) / d2, 0.0, 1.0) : 0.0;
        if ((centre - (a + s * d)).norm() > reach + half_diagonal) continue;
        const auto it = cells_.find(key(i, j, k));
        if (it != cells_.end()) out.insert(out.end(), it->second.begin(), it->second.end());
      }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

std::optional<double> EdgeProximity::nearest_m(const Vec3& point) const {
  const Hit h = nearest_two(point)[0];
  if (h.edge == kNoEdge) return std::nullopt;
  return h.distance_m;
}

}  // namespace rfidray
