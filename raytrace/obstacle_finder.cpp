#include "raytrace/obstacle_finder.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "core/units.h"
#include "raytrace/scene.h"
#include "raytrace/segment_distance.h"
#include "raytrace/thin_posts.h"

namespace rfidray {
namespace {

// Roughly parallel edges (a post's two sides, a shelf lip's two edges), not a plate's corner.
constexpr double kParallelEdgesCos = 0.866;  // cos 30°
// Parallel plates: planes within 5° of parallel.
constexpr double kParallelPlanesCos = 0.9962;
// Knife-edge ν up to which a slab's edge matters: 0.225/ν ≥ 0.05 (ITU-R P.526-15 §4.1, J(ν) ≈ 6.9 + 20 log(ν + ...)
// for ν > 1 gives the diffracted field ≈ 0.225/ν of the free-space one).
constexpr double kSlabNuMax = 4.5;

Vec3 closest_on_edge(const Edge& e, const Vec3& p) {
  const double z = std::clamp((p - e.start).dot(e.direction), 0.0, e.length_m);
  return e.start + z * e.direction;
}

// Distance from `p` (on the facet's plane) to the border of the facet's bounding box, over the two axes along
// which the facet is widest (exact for an axis-aligned rectangle; an upper bound of the distance to its outline).
double box_border_distance(const Facet& f, const Vec3& p) {
  const Vec3 size = f.hi - f.lo;
  std::array<int, 3> axes{0, 1, 2};
  std::sort(axes.begin(), axes.end(), [&](int a, int b) { return size[a] > size[b]; });
  double d = 1e300;
  for (int k = 0; k < 2; ++k) {
    const int i = axes[k];
    d = std::min(d, std::min(p[i] - f.lo[i], f.hi[i] - p[i]));
  }
  return std::max(d, 0.0);
}

std::array<uint32_t, 2> faces(const Edge& e) { return {e.facet_a, e.half_plane() ? e.facet_a : e.facet_b}; }

bool inside_bounds(const Facet& f, const Vec3& p) {
  constexpr double kSlack_m = 1e-3;
  return (p.array() >= f.lo.array() - kSlack_m).all() && (p.array() <= f.hi.array() + kSlack_m).all();
}

}  // namespace

ObstacleSight find_obstacles(const Scene& scene, const EdgeProximity& edges, const Vec3& antenna, const Vec3& tag,
                             double frequency_hz, double reach_m, double surface_epsilon_m,
                             std::span<const uint32_t> post_of_edge) {
  ObstacleSight out;
  const Vec3 span = tag - antenna;
  const double length = span.norm();
  if (!antenna.allFinite() || !tag.allFinite() || !(length > 2.0 * surface_epsilon_m) || scene.empty() ||
      !(frequency_hz > 0.0))
    return out;
  const Vec3 dir = span / length;
  const double lambda = wavelength_m(frequency_hz);
  const auto& facets = scene.facets();
  const auto& materials = scene.materials();

  // What blocks the direct segment first.
  const RayHit hit = scene.bvh().intersect(antenna, dir, surface_epsilon_m, length - surface_epsilon_m);
  bool blocked_by_metal = false;
  Vec3 blocking_point = Vec3::Zero();
  if (hit.hit) {
    const uint32_t triangle = scene.triangle_id(hit.geom, hit.prim);
    blocking_point = antenna + hit.t * dir;
    blocked_by_metal = materials[scene.material_of(triangle)].perfect_conductor;
    if (!blocked_by_metal) {
      // A slab transmission: how near the slab's edge is to the crossing point, in Fresnel terms.
      double h = 1e300;
      if (const auto e = edges.nearest_m(blocking_point)) h = *e;
      if (const uint32_t f = scene.facet_of(triangle); f != kNoFacet)
        h = std::min(h, box_border_distance(facets[f], blocking_point));
      const double d1 = std::max(hit.t, 1e-6), d2 = std::max(length - hit.t, 1e-6);
      const double nu = h * std::sqrt(2.0 * length / (lambda * d1 * d2));
      if (nu <= kSlabNuMax) out.slab = SlabCrossing{h, nu};
    }
  }

  // A narrow obstacle near an end, or where metal blocks the direct segment.
  struct Probe {
    Vec3 at;
    double reach;
  };
  Probe probes[3] = {{tag, reach_m}, {antenna, reach_m}, {blocking_point, edges.radius_m()}};
  const int n_probes = blocked_by_metal ? 3 : 2;
  for (int i = 0; i < n_probes && !out.narrow; ++i) {
    const auto two = edges.nearest_two(probes[i].at);
    if (two[1].edge == kNoEdge || two[1].distance_m > probes[i].reach) continue;
    const Edge& e1 = edges.edge(two[0].edge);
    const Edge& e2 = edges.edge(two[1].edge);
    if (std::abs(e1.direction.dot(e2.direction)) < kParallelEdgesCos) continue;
    const double width = (closest_on_edge(e1, probes[i].at) - closest_on_edge(e2, probes[i].at)).norm();
    if (!(width <= 0.5 * lambda)) continue;
    const SegmentClosest closest = closest_points(antenna, dir, length, e1.start, e1.direction, e1.length_m);
    const double clearance = closest.distance_m, s = closest.s_m;
    const double radius = std::sqrt(lambda * s * (length - s) / length);
    // This obstacle blocks the segment when the blocking point lies within λ/2 of its nearer edge.
    const bool blocks = blocked_by_metal && (closest_on_edge(e1, blocking_point) - blocking_point).norm() <= 0.5 * lambda;
    const bool post = !post_of_edge.empty() && post_of_edge[two[0].edge] != kNoPost &&
                      post_of_edge[two[0].edge] == post_of_edge[two[1].edge];
    // Off the line: only a modelled post near an end counts (its near field reaches the end).
    const bool off_line = !blocks && clearance > radius;
    if (off_line && !(post && i < 2 && two[0].distance_m * 2.0 * kPi / lambda <= kModelledPostNearEndKrho)) continue;
    out.narrow = NarrowObstacle{width,     two[0].distance_m, blocks ? 0.0 : clearance, radius, blocks, i < 2, post,
                                off_line};
  }

  // An end behind a penetrable slab's plane, near its edge (within the index's radius).
  for (int i = 0; i < 2 && !out.beyond_slab_edge; ++i) {
    const Vec3& end = i == 0 ? tag : antenna;
    const Vec3& other = i == 0 ? antenna : tag;
    const EdgeProximity::Hit nearest = edges.nearest_two(end)[0];
    if (nearest.edge == kNoEdge) continue;
    const Edge& e = edges.edge(nearest.edge);
    bool penetrable = false;
    for (uint32_t f : faces(e)) penetrable |= !materials[facets[f].material].perfect_conductor;
    const Facet& face = facets[e.facet_a];
    if (penetrable && face.signed_distance(end) * face.signed_distance(other) < 0.0)
      out.beyond_slab_edge = PenetrableEdge{nearest.distance_m};
  }

  // Parallel metal plates at an end.
  for (const Vec3& end : {tag, antenna}) {
    if (out.plates) break;
    const auto two = edges.nearest_two(end);
    if (two[1].edge == kNoEdge || two[1].distance_m > reach_m) continue;
    for (uint32_t fa : faces(edges.edge(two[0].edge))) {
      for (uint32_t fb : faces(edges.edge(two[1].edge))) {
        if (fa == fb || out.plates) continue;
        const Facet& a = facets[fa];
        const Facet& b = facets[fb];
        if (!materials[a.material].perfect_conductor || !materials[b.material].perfect_conductor) continue;
        const double cosine = a.normal.dot(b.normal);
        if (std::abs(cosine) < kParallelPlanesCos) continue;
        const double sa = a.signed_distance(end), sb = (cosine > 0.0 ? 1.0 : -1.0) * b.signed_distance(end);
        const double gap = std::abs(sa - sb);
        if (!(sa * sb < 0.0) || gap < 0.25 * lambda || gap > 2.0 * lambda) continue;
        const bool inside = inside_bounds(a, end - sa * a.normal) && inside_bounds(b, end - b.signed_distance(end) * b.normal);
        out.plates = ParallelPlates{gap, inside};
      }
    }
  }
  return out;
}

}  // namespace rfidray
