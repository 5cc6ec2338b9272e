#include "raytrace/thin_posts.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "core/logarithmic_capacity.h"
#include "raytrace/scene.h"

namespace rfidray {
namespace {

constexpr double kParallel = 1e-3;  // rad: edges and faces this close to parallel to the axis count as parallel

uint32_t find_root(std::vector<uint32_t>& parent, uint32_t i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

// The convex hull of 2-D points (Andrew's monotone chain), counter-clockwise, without repeated or collinear points.
std::vector<Eigen::Vector2d> convex_hull(std::vector<Eigen::Vector2d> p) {
  std::sort(p.begin(), p.end(), [](const auto& a, const auto& b) { return a.x() != b.x() ? a.x() < b.x() : a.y() < b.y(); });
  const auto cross = [](const Eigen::Vector2d& o, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
  };
  std::vector<Eigen::Vector2d> h(2 * p.size());
  size_t k = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    while (k >= 2 && cross(h[k - 2], h[k - 1], p[i]) <= 1e-14) --k;
    h[k++] = p[i];
  }
  for (size_t i = p.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross(h[k - 2], h[k - 1], p[i]) <= 1e-14) --k;
    h[k++] = p[i];
  }
  h.resize(k > 1 ? k - 1 : k);
  return h;
}

}  // namespace

ThinPosts find_thin_posts(const Scene& scene, const std::vector<Edge>& edges, double max_width_m) {
  ThinPosts out;
  out.post_of_facet.assign(scene.facets().size(), kNoPost);
  out.post_of_edge.assign(edges.size(), kNoPost);
  if (!(max_width_m > 0.0)) return out;
  const auto& facets = scene.facets();
  const auto& materials = scene.materials();
  const auto metal_side = [&](uint32_t f, const Vec3& d) {
    return f != kNoFacet && materials[facets[f].material].perfect_conductor &&
           std::abs(facets[f].normal.dot(d)) < kParallel;
  };
  // Candidate side edges: their faces metal and parallel to them. Joined through shared faces when parallel.
  std::vector<uint32_t> parent(edges.size());
  std::iota(parent.begin(), parent.end(), 0u);
  std::vector<std::vector<uint32_t>> edges_of_facet(facets.size());
  std::vector<char> candidate(edges.size(), 0);
  for (uint32_t i = 0; i < edges.size(); ++i) {
    const Edge& e = edges[i];
    if (!metal_side(e.facet_a, e.direction) || (!e.half_plane() && !metal_side(e.facet_b, e.direction))) continue;
    candidate[i] = 1;
    edges_of_facet[e.facet_a].push_back(i);
    if (!e.half_plane()) edges_of_facet[e.facet_b].push_back(i);
  }
  for (const auto& list : edges_of_facet)
    for (size_t i = 0; i < list.size(); ++i)
      for (size_t j = i + 1; j < list.size(); ++j)
        if (std::abs(edges[list[i]].direction.dot(edges[list[j]].direction)) > 1.0 - kParallel * kParallel)
          parent[find_root(parent, list[j])] = find_root(parent, list[i]);
  std::vector<std::vector<uint32_t>> components(edges.size());
  for (uint32_t i = 0; i < edges.size(); ++i)
    if (candidate[i]) components[find_root(parent, i)].push_back(i);

  std::vector<std::pair<std::vector<Eigen::Vector2d>, double>> shapes;  // cross-sections about their centroid
  for (const auto& comp : components) {
    if (comp.size() < 2) continue;
    const Vec3 d = edges[comp[0]].direction;
    bool parallel = true;
    std::vector<uint32_t> sides;
    for (uint32_t i : comp) {
      const Edge& e = edges[i];
      parallel = parallel && std::abs(e.direction.dot(d)) > 1.0 - kParallel * kParallel;
      sides.push_back(e.facet_a);
      if (!e.half_plane()) sides.push_back(e.facet_b);
    }
    if (!parallel) continue;
    std::sort(sides.begin(), sides.end());
    sides.erase(std::unique(sides.begin(), sides.end()), sides.end());
    // Every side must be a face between the post's own edges: each side facet's candidate edges all in this
    // component (a face shared with something else is not a post's).
    bool own = true;
    for (uint32_t f : sides)
      for (uint32_t i : edges_of_facet[f])
        own = own && (std::abs(edges[i].direction.dot(d)) < 1.0 - kParallel * kParallel ||
                      find_root(parent, i) == find_root(parent, comp[0]));
    if (!own) continue;
    // Cross-section: the sides' vertices in a plane ⟂ d; axial extent along d.
    const Vec3 u = d.unitOrthogonal(), v = d.cross(u);
    const Vec3 origin = edges[comp[0]].start;
    std::vector<Eigen::Vector2d> points;
    double z_lo = std::numeric_limits<double>::infinity(), z_hi = -z_lo;
    for (uint32_t f : sides)
      for (uint32_t tri : facets[f].triangles)
        for (const Vec3& c : scene.corners(tri)) {
          const Vec3 r = c - origin;
          points.emplace_back(r.dot(u), r.dot(v));
          z_lo = std::min(z_lo, r.dot(d));
          z_hi = std::max(z_hi, r.dot(d));
        }
    const std::vector<Eigen::Vector2d> hull = convex_hull(points);
    if (hull.size() < 2) continue;
    double width = 0.0;
    for (size_t i = 0; i < hull.size(); ++i)
      for (size_t j = i + 1; j < hull.size(); ++j) width = std::max(width, (hull[i] - hull[j]).norm());
    const double length = z_hi - z_lo;
    if (width > max_width_m || length < 4.0 * width) continue;
    // Centroid: of the hull's area, or the segment's midpoint.
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    double area = 0.0;
    if (hull.size() >= 3) {
      for (size_t i = 0; i < hull.size(); ++i) {
        const auto& p = hull[i];
        const auto& q = hull[(i + 1) % hull.size()];
        const double w = p.x() * q.y() - q.x() * p.y();
        area += w;
        centre += w * (p + q);
      }
    }
    // Compact cross-sections only (area ≥ 0.2 width²: a rectangle up to ~4.5 : 1): across the axis (hard case) a
    // flat strip or an angle scatters by its orientation, which the equivalent circle does not have.
    if (std::abs(0.5 * area) < 0.2 * width * width) continue;
    centre /= 3.0 * area;
    ThinPost post;
    post.direction = d;
    post.base = origin + centre.x() * u + centre.y() * v + z_lo * d;
    post.length_m = length;
    post.width_m = width;
    // Warehouses repeat one post: its capacity (an LU of 160 panels) once per distinct cross-section.
    std::vector<Eigen::Vector2d> shape;
    for (const auto& h : hull) shape.push_back(h - centre);
    const auto same = std::find_if(shapes.begin(), shapes.end(), [&](const auto& known) {
      if (known.first.size() != shape.size()) return false;
      for (size_t i = 0; i < shape.size(); ++i)
        if ((known.first[i] - shape[i]).norm() > 1e-9) return false;
      return true;
    });
    if (same != shapes.end()) {
      post.radius_m = same->second;
    } else {
      post.radius_m = logarithmic_capacity_m(hull);
      shapes.emplace_back(shape, post.radius_m);
    }
    post.material = facets[sides[0]].material;
    const uint32_t id = static_cast<uint32_t>(out.posts.size());
    out.posts.push_back(post);
    for (uint32_t f : sides) out.post_of_facet[f] = id;
    for (uint32_t i : comp) out.post_of_edge[i] = id;
  }
  // Caps and the edges round them: an edge with one face a post's side and the other (if any) a facet lying
  // inside that post's cross-section (its vertices within the hull's width of the axis, at one of its ends).
  for (uint32_t i = 0; i < edges.size(); ++i) {
    const Edge& e = edges[i];
    if (out.post_of_edge[i] != kNoPost) continue;
    const uint32_t pa = out.post_of_facet[e.facet_a];
    const uint32_t pb = e.half_plane() ? kNoPost : out.post_of_facet[e.facet_b];
    const uint32_t id = pa != kNoPost ? pa : pb;
    if (id == kNoPost) continue;
    const uint32_t other = pa != kNoPost ? e.facet_b : e.facet_a;
    if (other != kNoFacet && out.post_of_facet[other] != id) {
      const ThinPost& post = out.posts[id];
      bool inside = true;
      for (uint32_t tri : facets[other].triangles)
        for (const Vec3& c : scene.corners(tri)) {
          const Vec3 r = c - post.base;
          const double z = r.dot(post.direction);
          inside = inside && (r - z * post.direction).norm() <= post.width_m + 1e-6 &&
                   (std::abs(z) < 1e-4 || std::abs(z - post.length_m) < 1e-4);
        }
      if (!inside || out.post_of_facet[other] != kNoPost) continue;
      out.post_of_facet[other] = id;
    }
    out.post_of_edge[i] = id;
  }
  // A cap found after some of its edges were looked at: those edges too.
  for (uint32_t i = 0; i < edges.size(); ++i) {
    const Edge& e = edges[i];
    if (out.post_of_edge[i] != kNoPost) continue;
    const uint32_t pa = out.post_of_facet[e.facet_a];
    if (pa != kNoPost && (e.half_plane() || out.post_of_facet[e.facet_b] == pa)) out.post_of_edge[i] = pa;
  }
  return out;
}

}  // namespace rfidray
