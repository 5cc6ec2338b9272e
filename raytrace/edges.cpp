#include "raytrace/edges.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>

#include "core/units.h"
#include "raytrace/grid_key.h"
#include "raytrace/scene.h"

namespace rfidray {
namespace {

// A piece of a facet's outline: welded endpoint ids (sorted), positions, and a point inside the facet's
// triangle that owns it (to tell which way the facet lies from the edge).
struct OutlinePiece {
  uint32_t facet;
  Vec3 p0, p1;
  Vec3 inside;
};

bool point_in_facet(const Scene& scene, const Facet& facet, const Vec3& p, double tol) {
  if (std::abs(facet.signed_distance(p)) > tol) return false;
  if ((p.array() < facet.lo.array() - tol).any() || (p.array() > facet.hi.array() + tol).any()) return false;
  for (uint32_t tri : facet.triangles) {
    const auto c = scene.corners(tri);
    bool pos = true, neg = true;
    for (int k = 0; k < 3; ++k) {
      const Vec3 e = c[(k + 1) % 3] - c[k];
      const double s = facet.normal.dot(e.cross(p - c[k]));
      pos = pos && s >= -tol * e.norm();
      neg = neg && s <= tol * e.norm();
    }
    if (pos || neg) return true;
  }
  return false;
}

// Facets by 1 m cells of their bounds, to find the facets near a point (junction test) without a full scan.
class FacetGrid {
 public:
  explicit FacetGrid(const Scene& scene) {
    const auto& facets = scene.facets();
    for (uint32_t f = 0; f < facets.size(); ++f) {
      const auto lo = cell(facets[f].lo), hi = cell(facets[f].hi);
      const double cells = double(hi[0] - lo[0] + 1) * double(hi[1] - lo[1] + 1) * double(hi[2] - lo[2] + 1);
      if (cells > 4096.0) {
        large_.push_back(f);
        continue;
      }
      for (int64_t x = lo[0]; x <= hi[0]; ++x)
        for (int64_t y = lo[1]; y <= hi[1]; ++y)
          for (int64_t z = lo[2]; z <= hi[2]; ++z) cells_[{x, y, z}].push_back(f);
    }
  }
  template <class Fn>
  void near(const Vec3& p, Fn&& fn) const {
    for (uint32_t f : large_) fn(f);
    const auto c = cell(p);
    if (const auto it = cells_.find({c[0], c[1], c[2]}); it != cells_.end())
      for (uint32_t f : it->second) fn(f);
  }

 private:
  static std::array<int64_t, 3> cell(const Vec3& p) {
    return {static_cast<int64_t>(std::floor(p.x())), static_cast<int64_t>(std::floor(p.y())),
            static_cast<int64_t>(std::floor(p.z()))};
  }
  std::unordered_map<GridKey, std::vector<uint32_t>, GridHash> cells_;
  std::vector<uint32_t> large_;
};

// Unit vector in the plane with normal n, perpendicular to d, pointing towards `inside` from `on_edge`.
Vec3 into_face(const Vec3& n, const Vec3& d, const Vec3& on_edge, const Vec3& inside) {
  Vec3 t = n.cross(d).normalized();
  if (t.dot(inside - on_edge) < 0.0) t = -t;
  return t;
}

}  // namespace

std::vector<Edge> extract_edges(const Scene& scene, const EdgeOptions& options) {
  const auto& facets = scene.facets();
  const Vec3 origin = scene.local_origin();
  // Weld every facet vertex across meshes (1 µm grid, as merge_facets does within a mesh).
  // Ids in the order points are first met, as a std::map gave them (the edges' order follows from them). A mesh
  // vertex looks its point up once; its other corners read the id it got (a lookup per corner missed cache).
  const auto& meshes = scene.meshes();
  constexpr uint32_t kUnwelded = std::numeric_limits<uint32_t>::max();
  std::vector<std::vector<uint32_t>> weld(meshes.size());  // per mesh vertex: its id, or kUnwelded
  size_t vertices = 0;
  for (size_t m = 0; m < meshes.size(); ++m) {
    weld[m].assign(meshes[m].vertex_count(), kUnwelded);
    vertices += meshes[m].vertex_count();
  }
  std::unordered_map<GridKey, uint32_t, GridHash> ids;
  ids.reserve(vertices);
  auto id_of = [&](uint32_t mesh, uint32_t vertex, const Vec3& v) {
    uint32_t& id = weld[mesh][vertex];
    if (id == kUnwelded) {
      const Vec3 r = (v - origin) * 1e6;
      id = ids.emplace(GridKey{std::llround(r.x()), std::llround(r.y()), std::llround(r.z())},
                       static_cast<uint32_t>(ids.size()))
               .first->second;
    }
    return id;
  };
  // Outline pieces of every facet: triangle edges used once inside it, keyed by their welded ends, in facet order.
  std::vector<std::pair<uint64_t, OutlinePiece>> pieces;
  pieces.reserve(scene.triangle_count() + scene.triangle_count() / 2);  // ~1.2 per triangle on w1m; grown copies cost
  std::vector<std::pair<uint64_t, OutlinePiece>> facet_pieces;  // one facet's triangle edges, scratch
  for (uint32_t f = 0; f < facets.size(); ++f) {
    facet_pieces.clear();
    const uint32_t mesh = facets[f].mesh;
    const uint32_t first_triangle = scene.triangle_id(mesh, 0);
    for (uint32_t tri : facets[f].triangles) {
      const auto c = scene.corners(mesh, tri);
      const auto& v = meshes[mesh].triangles[tri - first_triangle];
      const Vec3 centroid = (c[0] + c[1] + c[2]) / 3.0;
      // In the order the edge loop below met them.
      const uint64_t id[3] = {id_of(mesh, v[0], c[0]), id_of(mesh, v[1], c[1]), id_of(mesh, v[2], c[2])};
      for (int k = 0; k < 3; ++k) {
        uint64_t a = id[k], b = id[(k + 1) % 3];
        if (a == b) continue;
        Vec3 pa = c[k], pb = c[(k + 1) % 3];
        if (a > b) {
          std::swap(a, b);
          std::swap(pa, pb);
        }
        facet_pieces.push_back({(a << 32) | b, OutlinePiece{f, pa, pb, centroid}});
      }
    }
    // A key met once is outline (the order among a key's pieces is then moot: they are dropped).
    std::sort(facet_pieces.begin(), facet_pieces.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (size_t i = 0; i < facet_pieces.size();) {
      size_t j = i + 1;
      while (j < facet_pieces.size() && facet_pieces[j].first == facet_pieces[i].first) ++j;
      if (j - i == 1) pieces.push_back(facet_pieces[i]);
      i = j;
    }
  }
  // By key, as a std::map<key, vector> of them iterated. Within a key the order is moot: one piece is a free edge,
  // two are ordered by their facets below, more are not an edge.
  std::sort(pieces.begin(), pieces.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
  // Classify each piece; collect wedge / free segments per (facet a, facet b).
  struct Segment {
    Vec3 p0, p1, inside_a, inside_b;
  };
  std::map<std::pair<uint32_t, uint32_t>, std::vector<Segment>> groups;
  const FacetGrid grid(scene);
  const double cos_flat = std::cos(options.flat_tolerance_rad);
  for (size_t first = 0; first < pieces.size();) {
    size_t last = first + 1;
    while (last < pieces.size() && pieces[last].first == pieces[first].first) ++last;
    const size_t count = last - first;  // outline pieces with these ends: 1 free, 2 between two facets
    const OutlinePiece& p = pieces[first].second;
    const OutlinePiece& other = pieces[std::min(first + 1, last - 1)].second;
    first = last;
    if (count == 1) {
      // A junction: the piece lies on another facet (tested at its midpoint and quarter points).
      bool junction = false;
      for (double s : {0.25, 0.5, 0.75}) {
        const Vec3 q = p.p0 + s * (p.p1 - p.p0);
        grid.near(q, [&](uint32_t g) {
          junction = junction || (g != p.facet && point_in_facet(scene, facets[g], q, options.junction_tolerance_m));
        });
      }
      if (!junction) groups[{p.facet, kNoEdge}].push_back({p.p0, p.p1, p.inside, p.inside});
    } else if (count == 2 && p.facet != other.facet) {
      const OutlinePiece& a = p.facet < other.facet ? p : other;
      const OutlinePiece& b = p.facet < other.facet ? other : p;
      if (std::abs(facets[a.facet].normal.dot(facets[b.facet].normal)) > cos_flat) continue;  // (near) coplanar
      groups[{a.facet, b.facet}].push_back({a.p0, a.p1, a.inside, b.inside});
    }
  }
  // Merge collinear, touching segments of each group into maximal edges.
  std::vector<Edge> edges;
  for (auto& group : groups) {
    // Named references, not a structured binding: clang 14 cannot capture those in the lambdas below.
    const auto& faces = group.first;
    auto& segments = group.second;
    // Canonical direction per segment (largest component positive), so collinear pieces compare equal.
    struct Oriented {
      Vec3 d, foot;
      double t0, t1;
      const Segment* s;
    };
    std::vector<Oriented> lines;
    for (const Segment& s : segments) {
      Vec3 d = (s.p1 - s.p0).normalized();
      int k = 0;
      d.cwiseAbs().maxCoeff(&k);
      if (d[k] < 0.0) d = -d;
      const Vec3 foot = s.p0 - (s.p0 - origin).dot(d) * d;
      double t0 = (s.p0 - origin).dot(d), t1 = (s.p1 - origin).dot(d);
      if (t0 > t1) std::swap(t0, t1);
      lines.push_back({d, foot, t0, t1, &s});
    }
    std::vector<char> used(lines.size(), 0);
    for (size_t i = 0; i < lines.size(); ++i) {
      if (used[i]) continue;
      // Every segment on the same line as segment i, in order along it.
      std::vector<size_t> on_line;
      for (size_t j = i; j < lines.size(); ++j)
        if (!used[j] && (lines[j].d - lines[i].d).norm() < 1e-6 && (lines[j].foot - lines[i].foot).norm() < 1e-6) {
          on_line.push_back(j);
          used[j] = 1;
        }
      std::sort(on_line.begin(), on_line.end(), [&](size_t x, size_t y) { return lines[x].t0 < lines[y].t0; });
      const Vec3& d = lines[i].d;
      const Facet& fa = facets[faces.first];
      auto emit = [&](double t0, double t1, const Segment& s) {
        Edge e;
        e.direction = d;
        e.start = lines[i].foot + t0 * d;  // the foot is the line's point with (x − origin)·d = 0
        e.length_m = t1 - t0;
        e.facet_a = faces.first;
        e.into_a = into_face(fa.normal, d, e.start, s.inside_a);
        if (faces.second == kNoEdge) {
          e.into_b = e.into_a;
          e.alpha_rad = kTwoPi;
        } else {
          e.facet_b = faces.second;
          e.into_b = into_face(facets[faces.second].normal, d, e.start, s.inside_b);
          double alpha = std::atan2(e.into_a.cross(e.into_b).dot(d), e.into_a.dot(e.into_b));
          if (alpha < 0.0) alpha += kTwoPi;
          e.alpha_rad = alpha;
        }
        if (e.length_m > 1e-9) edges.push_back(e);
      };
      double t0 = lines[on_line[0]].t0, t1 = lines[on_line[0]].t1;
      const Segment* first = lines[on_line[0]].s;
      for (size_t m = 1; m < on_line.size(); ++m) {
        const Oriented& o = lines[on_line[m]];
        if (o.t0 <= t1 + 1e-9) {
          t1 = std::max(t1, o.t1);
        } else {
          emit(t0, t1, *first);
          t0 = o.t0;
          t1 = o.t1;
          first = o.s;
        }
      }
      emit(t0, t1, *first);
    }
  }
  return edges;
}

}  // namespace rfidray
