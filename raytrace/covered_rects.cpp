#include "raytrace/covered_rects.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <tuple>

namespace rfidray {
namespace {

struct Uv {
  double u, v;
};

// Closed segment a–b against the closed rectangle [lo, hi] (Liang–Barsky in double).
bool segment_meets_rect(Uv a, Uv b, Uv lo, Uv hi) {
  double t0 = 0.0, t1 = 1.0;
  const double p[4] = {-(b.u - a.u), b.u - a.u, -(b.v - a.v), b.v - a.v};
  const double q[4] = {a.u - lo.u, hi.u - a.u, a.v - lo.v, hi.v - a.v};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
    } else {
      const double r = q[i] / p[i];
      if (p[i] < 0.0) t0 = std::max(t0, r);
      else t1 = std::min(t1, r);
      if (t0 > t1) return false;
    }
  }
  return true;
}

// 1 strictly inside, 0 strictly outside, −1 too close to an edge of the triangle to say.
int inside_triangle(const std::array<Uv, 3>& t, Uv s) {
  bool pos = false, neg = false, near = false;
  for (int i = 0; i < 3; ++i) {
    const Uv a = t[i], b = t[(i + 1) % 3];
    const double eu = b.u - a.u, ev = b.v - a.v;
    const double e = eu * (s.v - a.v) - ev * (s.u - a.u);
    const double len = std::sqrt(eu * eu + ev * ev);
    const double scale = len * (std::abs(s.u) + std::abs(s.v) + std::abs(a.u) + std::abs(a.v) + len);
    if (std::abs(e) <= 1e-12 * scale) near = true;
    else if (e > 0) pos = true;
    else neg = true;
  }
  if (pos && neg) return 0;  // outside (on the wrong side of some edge by more than rounding)
  return near ? -1 : 1;
}

float round_up(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) < x) f = std::nextafter(f, std::numeric_limits<float>::infinity());
  return f;
}
float round_down(double x) {
  float f = static_cast<float>(x);
  if (static_cast<double>(f) > x) f = std::nextafter(f, -std::numeric_limits<float>::infinity());
  return f;
}

}  // namespace

CoveredRects::CoveredRects(std::span<const SceneMesh> meshes, const Vec3& origin) : origin_(origin) {
  for (const SceneMesh& m : meshes)
    for (size_t i = 0; i < m.vertex_count(); ++i) magnitude_m_ = std::max(magnitude_m_, m.local_vertex(i).norm());
  // The margin: 1e-5 of the scene's size, at least 0.1 mm (blocks() uses a rectangle only where its own
  // error bound, 1e-6 relative, is at most half of it). Larger margins lose the thin faces that block most
  // legs in the warehouses (3 cm shelf-plate fronts: with 1e-4, 3.4 of 18 candidates per link culled on w1m,
  // with 1e-5, 16.9).
  margin_m_ = std::max(1e-4, 1e-5 * magnitude_m_);
  for (int k = 0; k < 3; ++k) build_axis(meshes, k);
  std::sort(order_.begin(), order_.end(),
            [&](int x, int y) { return grids_[x].entries.size() > grids_[y].entries.size(); });
}

size_t CoveredRects::rect_count() const {
  size_t n = 0;
  for (const AxisGrid& g : grids_) n += g.entries.size();
  return n;
}

std::vector<CoveredRects::Rect> CoveredRects::rects() const {
  std::vector<Rect> out;
  for (const AxisGrid& g : grids_)
    for (const Entry& e : g.entries)
      out.push_back({g.k, e.c, e.u_lo + origin_[g.u], e.u_hi + origin_[g.u], e.v_lo + origin_[g.v], e.v_hi + origin_[g.v]});
  return out;
}

size_t CoveredRects::bytes() const {
  size_t n = sizeof(*this);
  for (const AxisGrid& g : grids_) n += g.start.capacity() * sizeof(uint32_t) + g.entries.capacity() * sizeof(Entry);
  return n;
}

void CoveredRects::build_axis(std::span<const SceneMesh> meshes, int k) {
  AxisGrid& g = grids_[k];
  g.k = k, g.u = (k + 1) % 3, g.v = (k + 2) % 3;
  struct Tri {
    double c;
    uint32_t mesh, tri;
  };
  std::vector<Tri> tris;
  double ulo = INFINITY, uhi = -INFINITY, vlo = INFINITY, vhi = -INFINITY;
  for (uint32_t mi = 0; mi < meshes.size(); ++mi) {
    const SceneMesh& m = meshes[mi];
    for (uint32_t ti = 0; ti < m.triangles.size(); ++ti) {
      const auto& t = m.triangles[ti];
      // Bitwise equal float coordinates: the plane Embree's triangles lie in (world c = origin + float).
      const float ck = m.vertex_xyz[3 * t[0] + k];
      if (m.vertex_xyz[3 * t[1] + k] != ck || m.vertex_xyz[3 * t[2] + k] != ck || !std::isfinite(ck)) continue;
      const double c = origin_[k] + double(ck);
      tris.push_back({c, mi, ti});
      for (uint32_t vi : t) {
        const double pu = m.vertex_xyz[3 * vi + g.u], pv = m.vertex_xyz[3 * vi + g.v];
        ulo = std::min(ulo, pu), uhi = std::max(uhi, pu), vlo = std::min(vlo, pv), vhi = std::max(vhi, pv);
      }
    }
  }
  if (tris.empty()) return;
  // ~128 of these triangles per cell, square cells, at most 2^22 cells (on w1m: 8.2 bytes per triangle; 8 per
  // cell held 41 and walked more cells for no more culling; a cell's planes are found by binary search).
  const double eu = std::max(uhi - ulo, 1e-3), ev = std::max(vhi - vlo, 1e-3);
  const double target = std::clamp(static_cast<double>(tris.size()) / 128.0, 1.0, 4194304.0);
  g.h = std::max({std::sqrt(eu * ev / target), eu / 2048.0, ev / 2048.0}) * (1.0 + 1e-9);
  g.inv_h = 1.0 / g.h;
  g.nu = static_cast<int>(eu * g.inv_h) + 1;
  g.nv = static_cast<int>(ev * g.inv_h) + 1;
  g.u0 = ulo, g.v0 = vlo;
  const auto cell_of = [&](double x, double x0, int n) {
    return std::clamp(static_cast<int>(std::floor((x - x0) * g.inv_h)), 0, n - 1);
  };
  std::sort(tris.begin(), tris.end(), [](const Tri& a, const Tri& b) { return std::tie(a.c, a.mesh, a.tri) < std::tie(b.c, b.mesh, b.tri); });
  const double m = margin_m_;
  std::vector<std::pair<uint32_t, Entry>> found;  // (cell, entry)
  // Scratch reused across planes.
  struct Edge {
    Uv a, b;
    uint32_t tri;
  };
  std::vector<Edge> edges;
  std::vector<std::array<Uv, 3>> corner;
  std::vector<uint32_t> parent;
  std::vector<std::pair<Uv, Uv>> odd;
  std::vector<std::pair<uint32_t, uint32_t>> tri_cells, odd_cells;  // (cell, index)
  std::vector<std::pair<uint32_t, uint32_t>> by_comp;               // (component, triangle) in one cell
  const auto find = [&](uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (size_t first = 0; first < tris.size();) {
    size_t last = first;
    while (last < tris.size() && tris[last].c == tris[first].c) ++last;
    const double c = tris[first].c;
    const size_t n = last - first;
    corner.resize(n);
    edges.clear();
    for (size_t i = 0; i < n; ++i) {
      const SceneMesh& mesh = meshes[tris[first + i].mesh];
      const auto& t = mesh.triangles[tris[first + i].tri];
      for (int j = 0; j < 3; ++j)
        corner[i][j] = {double(mesh.vertex_xyz[3 * t[j] + g.u]), double(mesh.vertex_xyz[3 * t[j] + g.v])};
      for (int j = 0; j < 3; ++j) {
        Uv a = corner[i][j], b = corner[i][(j + 1) % 3];
        if (std::tie(b.u, b.v) < std::tie(a.u, a.v)) std::swap(a, b);
        edges.push_back({a, b, static_cast<uint32_t>(i)});
      }
    }
    // Edges welded by exact position: odd ones bound the covered region; shared ones join components.
    std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
      return std::tie(x.a.u, x.a.v, x.b.u, x.b.v) < std::tie(y.a.u, y.a.v, y.b.u, y.b.v);
    });
    parent.resize(n);
    std::iota(parent.begin(), parent.end(), 0u);
    odd.clear();
    for (size_t i = 0; i < edges.size();) {
      size_t j = i + 1;
      const auto same = [&](const Edge& x, const Edge& y) {
        return x.a.u == y.a.u && x.a.v == y.a.v && x.b.u == y.b.u && x.b.v == y.b.v;
      };
      while (j < edges.size() && same(edges[j], edges[i])) {
        parent[find(edges[j].tri)] = find(edges[i].tri);
        ++j;
      }
      if ((j - i) % 2 == 1) odd.push_back({edges[i].a, edges[i].b});
      i = j;
    }
    // Bin triangles (by bounds) and odd edges (by bounds inflated by the margin) into cells.
    tri_cells.clear();
    odd_cells.clear();
    const auto bin = [&](double u_lo, double u_hi, double v_lo, double v_hi, uint32_t idx, auto& out) {
      const int iu0 = cell_of(u_lo, g.u0, g.nu), iu1 = cell_of(u_hi, g.u0, g.nu);
      const int iv0 = cell_of(v_lo, g.v0, g.nv), iv1 = cell_of(v_hi, g.v0, g.nv);
      for (int iv = iv0; iv <= iv1; ++iv)
        for (int iu = iu0; iu <= iu1; ++iu) out.push_back({static_cast<uint32_t>(iv * g.nu + iu), idx});
    };
    for (uint32_t i = 0; i < n; ++i) {
      const auto& t = corner[i];
      bin(std::min({t[0].u, t[1].u, t[2].u}), std::max({t[0].u, t[1].u, t[2].u}), std::min({t[0].v, t[1].v, t[2].v}),
          std::max({t[0].v, t[1].v, t[2].v}), i, tri_cells);
    }
    for (uint32_t i = 0; i < odd.size(); ++i) {
      const auto& [a, b] = odd[i];
      const double pad = 2.0 * m;
      bin(std::min(a.u, b.u) - pad, std::max(a.u, b.u) + pad, std::min(a.v, b.v) - pad, std::max(a.v, b.v) + pad, i,
          odd_cells);
    }
    std::sort(tri_cells.begin(), tri_cells.end());
    std::sort(odd_cells.begin(), odd_cells.end());
    for (size_t i = 0; i < tri_cells.size();) {
      const uint32_t cell = tri_cells[i].first;
      size_t j = i;
      while (j < tri_cells.size() && tri_cells[j].first == cell) ++j;
      const auto seg_begin = std::lower_bound(odd_cells.begin(), odd_cells.end(), std::pair<uint32_t, uint32_t>{cell, 0});
      auto seg_end = seg_begin;
      while (seg_end != odd_cells.end() && seg_end->first == cell) ++seg_end;
      const int iu = static_cast<int>(cell % g.nu), iv = static_cast<int>(cell / g.nu);
      const Uv cell_lo{g.u0 + iu * g.h, g.v0 + iv * g.h}, cell_hi{g.u0 + (iu + 1) * g.h, g.v0 + (iv + 1) * g.h};
      by_comp.clear();
      for (size_t q = i; q < j; ++q) by_comp.push_back({find(tri_cells[q].second), tri_cells[q].second});
      std::sort(by_comp.begin(), by_comp.end());
      for (size_t a = 0; a < by_comp.size();) {
        size_t b = a;
        Uv lo{INFINITY, INFINITY}, hi{-INFINITY, -INFINITY};
        for (; b < by_comp.size() && by_comp[b].first == by_comp[a].first; ++b)
          for (const Uv& p : corner[by_comp[b].second])
            lo = {std::min(lo.u, p.u), std::min(lo.v, p.v)}, hi = {std::max(hi.u, p.u), std::max(hi.v, p.v)};
        a = b;
        lo = {std::max(lo.u, cell_lo.u), std::max(lo.v, cell_lo.v)};
        hi = {std::min(hi.u, cell_hi.u), std::min(hi.v, cell_hi.v)};
        // R = the component's bounds in the cell; if R⁺ reaches an odd edge, R shrunk by two margins.
        const auto clear_of_odd = [&](Uv rlo, Uv rhi) {
          const Uv plo{rlo.u - m, rlo.v - m}, phi{rhi.u + m, rhi.v + m};
          for (auto s = seg_begin; s != seg_end; ++s)
            if (segment_meets_rect(odd[s->second].first, odd[s->second].second, plo, phi)) return false;
          return true;
        };
        bool ok = lo.u < hi.u && lo.v < hi.v && clear_of_odd(lo, hi);
        if (!ok) {
          lo = {lo.u + 2 * m, lo.v + 2 * m}, hi = {hi.u - 2 * m, hi.v - 2 * m};
          ok = lo.u < hi.u && lo.v < hi.v && clear_of_odd(lo, hi);
        }
        if (!ok) continue;
        // Covering parity at a sample point of R (any triangle containing it is binned in this cell); a
        // sample on some triangle's edge is ambiguous, so try another.
        static constexpr double kSamples[4][2] = {{0.5, 0.5}, {0.31, 0.67}, {0.73, 0.29}, {0.53, 0.41}};
        int parity = -1;
        for (const auto& f : kSamples) {
          const Uv s{lo.u + f[0] * (hi.u - lo.u), lo.v + f[1] * (hi.v - lo.v)};
          int count = 0;
          bool ambiguous = false;
          for (size_t q = i; q < j && !ambiguous; ++q) {
            const int in = inside_triangle(corner[tri_cells[q].second], s);
            if (in < 0) ambiguous = true;
            count += in > 0;
          }
          if (!ambiguous) {
            parity = count % 2;
            break;
          }
        }
        if (parity != 1) continue;
        const Entry e{c, round_up(lo.u), round_down(hi.u), round_up(lo.v), round_down(hi.v)};
        if (e.u_lo < e.u_hi && e.v_lo < e.v_hi) found.push_back({cell, e});
      }
      i = j;
    }
    first = last;
  }
  std::sort(found.begin(), found.end(), [](const auto& x, const auto& y) {
    return std::tie(x.first, x.second.c) < std::tie(y.first, y.second.c);
  });
  const size_t cells = static_cast<size_t>(g.nu) * g.nv;
  g.start.assign(cells + 1, 0);
  for (const auto& [cell, e] : found) ++g.start[cell + 1];
  for (size_t i = 0; i < cells; ++i) g.start[i + 1] += g.start[i];
  g.entries.reserve(found.size());
  for (const auto& fe : found) g.entries.push_back(fe.second);
  if (g.entries.empty()) {  // nothing to test on this axis
    g.nu = g.nv = 0;
    g.start = {};
    g.entries = {};
  }
}

bool CoveredRects::blocks(const Vec3& o, const Vec3& d, double tnear, double tfar) const {
  if (!(tfar > tnear)) return false;
  const double err = 1e-6 * (magnitude_m_ + (o - origin_).norm() + std::abs(tfar));
  for (int k : order_) {
    const AxisGrid& g = grids_[k];
    if (g.nu == 0) continue;
    const double adk = std::abs(d[k]);
    if (!(adk > 0.0)) continue;                    // parallel to this axis's planes
    const double slack = err * (1.0 + 1.0 / adk);  // the float crossing's error along the ray and across it
    if (!(slack <= 0.5 * margin_m_)) continue;     // too flat to decide here
    const double ta = tnear + slack, tb = tfar - slack;
    if (!(ta < tb)) continue;
    if (blocks_axis(g, o, d, ta, tb, slack)) return true;
  }
  return false;
}

bool CoveredRects::blocks_axis(const AxisGrid& g, const Vec3& o, const Vec3& d, double ta, double tb,
                               double slack) const {
  // (u, v) about the local origin, as the grid and rectangles are stored; k and c in world coordinates.
  const double ou = o[g.u] - origin_[g.u], ov = o[g.v] - origin_[g.v], ok = o[g.k];
  const double du = d[g.u], dv = d[g.v], dk = d[g.k];
  const double inv_dk = 1.0 / dk;
  // Clip [ta, tb] to the grid's extent (a crossing outside it has no rectangle).
  double t0 = ta, t1 = tb;
  const auto clip = [&](double p, double q, double lo, double hi) {
    if (q == 0.0) return p >= lo && p <= hi;
    double s0 = (lo - p) / q, s1 = (hi - p) / q;
    if (s0 > s1) std::swap(s0, s1);
    t0 = std::max(t0, s0), t1 = std::min(t1, s1);
    return t0 <= t1;
  };
  if (!clip(ou, du, g.u0, g.u0 + g.nu * g.h) || !clip(ov, dv, g.v0, g.v0 + g.nv * g.h)) return false;
  // 2-D DDA over the cells the segment's (u, v) projection crosses (Amanatides & Woo 1987).
  int iu = std::clamp(static_cast<int>(std::floor((ou + t0 * du - g.u0) * g.inv_h)), 0, g.nu - 1);
  int iv = std::clamp(static_cast<int>(std::floor((ov + t0 * dv - g.v0) * g.inv_h)), 0, g.nv - 1);
  const int su = du > 0 ? 1 : du < 0 ? -1 : 0, sv = dv > 0 ? 1 : dv < 0 ? -1 : 0;
  double next_u = su > 0 ? (g.u0 + (iu + 1) * g.h - ou) / du : su < 0 ? (g.u0 + iu * g.h - ou) / du : INFINITY;
  double next_v = sv > 0 ? (g.v0 + (iv + 1) * g.h - ov) / dv : sv < 0 ? (g.v0 + iv * g.h - ov) / dv : INFINITY;
  const double step_u = su ? g.h / std::abs(du) : INFINITY, step_v = sv ? g.h / std::abs(dv) : INFINITY;
  double t = t0;
  for (int steps = g.nu + g.nv + 2; steps > 0; --steps) {
    const double t_exit = std::min({next_u, next_v, t1});
    const size_t cell = static_cast<size_t>(iv) * g.nu + iu;
    const uint32_t e0 = g.start[cell], e1 = g.start[cell + 1];
    if (e0 != e1) {
      // Planes the segment crosses in this cell (a generous filter; the tests below decide).
      const double k0 = ok + t * dk, k1 = ok + t_exit * dk;
      const double lo = std::min(k0, k1) - slack - 1e-9, hi = std::max(k0, k1) + slack + 1e-9;
      // A cell can hold the planes of a whole row of racks (ascending c): skip to the first one ≥ lo.
      const Entry* first = g.entries.data() + e0;
      const Entry* end = g.entries.data() + e1;
      for (size_t n = e1 - e0; n > 1;) {  // branch-free lower bound: the first entry may still be < lo
        const size_t half = n / 2;
        first = first[half - 1].c < lo ? first + half : first;
        n -= half;
      }
      for (const Entry* it = first; it != end; ++it) {
        const Entry& e = *it;
        if (e.c < lo) continue;
        if (e.c > hi) break;
        const double tc = (e.c - ok) * inv_dk;
        if (!(tc >= ta && tc <= tb)) continue;
        const double qu = ou + tc * du, qv = ov + tc * dv;
        if (qu >= e.u_lo && qu <= e.u_hi && qv >= e.v_lo && qv <= e.v_hi) return true;
      }
    }
    if (t_exit >= t1) break;
    if (next_u < next_v) {
      iu += su, t = next_u, next_u += step_u;
      if (iu < 0 || iu >= g.nu) break;
    } else {
      iv += sv, t = next_v, next_v += step_v;
      if (iv < 0 || iv >= g.nv) break;
    }
  }
  return false;
}

}  // namespace rfidray
