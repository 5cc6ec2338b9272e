// The edge-on plate check (raytrace/edge_on_plate_finder.h).
#include "raytrace/edge_on_plate_finder.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/units.h"
#include "raytrace/scene.h"
#include "raytrace/segment_distance.h"
#include "raytrace/thin_posts.h"

namespace rfidray {
namespace {

constexpr double kParallelCos = 0.8660254037844387;  // cos 30°

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
    const SegmentClosest closest = closest_points(a, u_hat, length, e.start, e.direction, e.length_m);
    const double s = closest.s_m / length;
    if (!(s > 0.0 && s < 1.0)) continue;  // not beside the segment
    const Vec3 on_edge = e.start + closest.t_m * e.direction;
    const double distance = closest.distance_m;
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
