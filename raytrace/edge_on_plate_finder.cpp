// The edge-on plate check (raytrace/edge_on_plate_finder.h).
#include "raytrace/edge_on_plate_finder.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/units.h"
#include "raytrace/scene.h"
#include "raytrace/thin_posts.h"

namespace rfidray {
namespace {

constexpr double kParallelCos = 0.8660254037844387;  // cos 30°

// Closest points of segments p0 + s·(p1 − p0) and q0 + u·(q1 − q0), s, u in [0, 1] (C. Ericson, "Real-Time
// Collision Detection", 2005, §5.1.9).
void closest_points(const Vec3& p0, const Vec3& p1, const Vec3& q0, const Vec3& q1, double& s, double& u) {
  const Vec3 d1 = p1 - p0, d2 = q1 - q0, r = p0 - q0;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  const double c = d1.dot(r), b = d1.dot(d2), denom = a * e - b * b;
  s = denom > 1e-14 * a * e ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  u = (b * s + f) / e;
  if (u < 0.0) {
    u = 0.0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (u > 1.0) {
    u = 1.0;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
}

struct NearEdge {
  uint32_t edge;
  Vec3 point;  // on the edge, closest to the segment
  double distance_m, fresnel_radius_m;
};

}  // namespace

std::optional<EdgeOnPlate> find_edge_on_plate(const Scene& scene, const EdgeProximity& edges, const Vec3& a,
                                              const Vec3& t, double f, std::span<const uint32_t> post_of_edge) {
  const double length = (t - a).norm();
  if (!a.allFinite() || !t.allFinite() || !(length > 0.0)) return std::nullopt;
  const Vec3 u_hat = (t - a) / length;
  const double lambda = wavelength_m(f);
  const auto& facets = scene.facets();
  const auto& materials = scene.materials();
  const auto metal = [&](uint32_t facet) { return materials[facets[facet].material].perfect_conductor; };
  thread_local std::vector<NearEdge> near;  // per-thread scratch: no allocation once warm
  thread_local std::vector<uint32_t> candidates;
  near.clear();
  // The first Fresnel zone is widest mid-link: √(λ d/4). Only edges that close to the segment can be in it.
  edges.edges_near_segment(a, t, 0.5 * std::sqrt(lambda * length), candidates);
  for (uint32_t i : candidates) {
    if (!post_of_edge.empty() && post_of_edge[i] != kNoPost) continue;
    const Edge& e = edges.edge(i);
    if (!metal(e.facet_a) || (!e.half_plane() && !metal(e.facet_b))) continue;
    double s = 0.0, v = 0.0;
    const Vec3 e1 = e.start + e.length_m * e.direction;
    closest_points(a, t, e.start, e1, s, v);
    if (!(s > 0.0 && s < 1.0)) continue;  // not beside the segment
    const Vec3 on_edge = e.start + v * (e1 - e.start);
    const double distance = (a + s * (t - a) - on_edge).norm();
    const double radius = std::sqrt(lambda * s * (1.0 - s) * length);
    if (distance <= radius) near.push_back({i, on_edge, distance, radius});
  }
  std::optional<EdgeOnPlate> best;
  for (size_t i = 0; i < near.size(); ++i)
    for (size_t j = i + 1; j < near.size(); ++j) {
      const Edge& ei = edges.edge(near[i].edge);
      const Edge& ej = edges.edge(near[j].edge);
      if (std::abs(ei.direction.dot(ej.direction)) < kParallelCos) continue;
      // One facet between them (a plate's two sides).
      const bool shared = ei.facet_a == ej.facet_a || ei.facet_a == ej.facet_b ||
                          (!ei.half_plane() && (ei.facet_b == ej.facet_a || ei.facet_b == ej.facet_b));
      if (!shared) continue;
      const Vec3 gap = near[j].point - near[i].point;
      const double along = std::abs(gap.dot(u_hat));
      const double across = (gap - gap.dot(u_hat) * u_hat).norm();
      if (along < 0.5 * lambda || across >= 0.5 * lambda) continue;
      if (best && across >= best->across_m) continue;
      const bool i_farther = near[i].distance_m >= near[j].distance_m;
      const NearEdge& farther = i_farther ? near[i] : near[j];
      best = EdgeOnPlate{along, across, farther.distance_m, farther.fresnel_radius_m};
    }
  return best;
}

}  // namespace rfidray
