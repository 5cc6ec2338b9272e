// Pairs of parallel edges (raytrace/edge_pairs.h): edges grouped by direction, then a sweep across the
// direction so that only edges near each other are compared.
#include "raytrace/edge_pairs.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>
#include <utility>

#include "raytrace/segment_distance.h"

namespace rfidray {
namespace {

constexpr double kParallelRad = 1e-6;
constexpr double kDistinctLinesM = 1e-6;

// The direction with its largest component positive: parallel and antiparallel edges get the same key.
Vec3 canonical_direction(const Vec3& d) {
  int axis = 0;
  for (int i = 1; i < 3; ++i)
    if (std::abs(d[i]) > std::abs(d[axis])) axis = i;
  return d[axis] < 0.0 ? Vec3(-d) : d;
}

}  // namespace

uint32_t facet_towards(const Edge& e, const Vec3& u) {
  constexpr double kAlong = 1.0 - 1e-9;
  if (e.into_a.dot(u) > kAlong) return e.facet_a;
  if (!e.half_plane() && e.into_b.dot(u) > kAlong) return e.facet_b;
  return kNoFacet;
}

std::vector<EdgePair> find_edge_pairs(std::span<const Edge> edges, std::span<const uint8_t> skip,
                                      double max_distance_m) {
  std::vector<EdgePair> pairs;
  if (!(max_distance_m > 0.0) || edges.size() < 2) return pairs;
  std::vector<Vec3> key(edges.size());
  std::vector<uint32_t> order;
  for (uint32_t i = 0; i < edges.size(); ++i) {
    if (i < skip.size() && skip[i]) continue;
    key[i] = canonical_direction(edges[i].direction);
    order.push_back(i);
  }
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    const Vec3 &x = key[a], &y = key[b];
    return std::tie(x[0], x[1], x[2], a) < std::tie(y[0], y[1], y[2], b);
  });
  std::vector<uint32_t> group;
  for (size_t g0 = 0; g0 < order.size();) {
    // One group: consecutive edges within kParallelRad of its first edge's direction.
    const Vec3 head = key[order[g0]];
    size_t g1 = g0 + 1;
    while (g1 < order.size() && key[order[g1]].cross(head).norm() <= kParallelRad) ++g1;
    group.assign(order.begin() + g0, order.begin() + g1);
    g0 = g1;
    if (group.size() < 2) continue;
    // Sweep along the axis most nearly perpendicular to the group's direction: the edges' extents there are
    // short, so each edge meets only its neighbours.
    int axis = 0;
    for (int i = 1; i < 3; ++i)
      if (std::abs(head[i]) < std::abs(head[axis])) axis = i;
    const auto end_coordinate = [&](uint32_t e) { return (edges[e].start + edges[e].length_m * edges[e].direction)[axis]; };
    const auto lo = [&](uint32_t e) { return std::min(edges[e].start[axis], end_coordinate(e)); };
    const auto hi = [&](uint32_t e) { return std::max(edges[e].start[axis], end_coordinate(e)); };
    std::sort(group.begin(), group.end(),
              [&](uint32_t a, uint32_t b) { return std::pair(lo(a), a) < std::pair(lo(b), b); });
    for (size_t x = 0; x < group.size(); ++x) {
      const Edge& ei = edges[group[x]];
      const double reach = hi(group[x]) + max_distance_m;
      for (size_t y = x + 1; y < group.size() && lo(group[y]) <= reach; ++y) {
        const Edge& ej = edges[group[y]];
        const Vec3& d = ei.direction;
        const Vec3 w = ej.start - ei.start;
        const Vec3 w_perp = w - w.dot(d) * d;
        const double distance = w_perp.norm();
        if (distance <= kDistinctLinesM || distance > max_distance_m) continue;
        // Extents along d: [0, len_i] and ej's, from its start along ±d.
        const double j0 = w.dot(d), j1 = j0 + ej.length_m * ej.direction.dot(d);
        const double gap = std::max({0.0, std::min(j0, j1) - ei.length_m, -std::max(j0, j1)});
        if (gap > max_distance_m) continue;
        EdgePair p;
        p.first = std::min(group[x], group[y]);
        p.second = std::max(group[x], group[y]);
        p.distance_m = distance;
        const Vec3 u = w_perp / distance;  // from ei towards ej
        const uint32_t fi = facet_towards(ei, u), fj = facet_towards(ej, -u);
        if (fi != kNoFacet && fi == fj) p.shared_facet = fi;
        pairs.push_back(p);
      }
    }
  }
  // Edges of one facet that are not parallel: the leg between them runs across the facet.
  std::vector<std::pair<uint32_t, uint32_t>> by_facet;  // (facet, edge)
  for (uint32_t i = 0; i < edges.size(); ++i) {
    if (i < skip.size() && skip[i]) continue;
    by_facet.emplace_back(edges[i].facet_a, i);
    if (!edges[i].half_plane()) by_facet.emplace_back(edges[i].facet_b, i);
  }
  std::sort(by_facet.begin(), by_facet.end());
  for (size_t f0 = 0; f0 < by_facet.size();) {
    size_t f1 = f0 + 1;
    while (f1 < by_facet.size() && by_facet[f1].first == by_facet[f0].first) ++f1;
    for (size_t x = f0; x < f1; ++x)
      for (size_t y = x + 1; y < f1; ++y) {
        const Edge& ei = edges[by_facet[x].second];
        const Edge& ej = edges[by_facet[y].second];
        if (ei.direction.cross(ej.direction).norm() <= kParallelRad) continue;  // parallel: found above
        const double distance = closest_points(ei.start, ei.direction, ei.length_m, ej.start, ej.direction, ej.length_m).distance_m;
        if (distance > max_distance_m) continue;
        EdgePair p;
        p.first = std::min(by_facet[x].second, by_facet[y].second);
        p.second = std::max(by_facet[x].second, by_facet[y].second);
        p.shared_facet = by_facet[x].first;
        p.distance_m = distance;
        p.parallel = false;
        pairs.push_back(p);
      }
    f0 = f1;
  }
  std::sort(pairs.begin(), pairs.end(),
            [](const EdgePair& a, const EdgePair& b) { return std::pair(a.first, a.second) < std::pair(b.first, b.second); });
  // Once per pair (two planar facets share at most one edge line, so this only guards degenerate meshes).
  pairs.erase(std::unique(pairs.begin(), pairs.end(),
                          [](const EdgePair& a, const EdgePair& b) { return a.first == b.first && a.second == b.second; }),
              pairs.end());
  for (EdgePair& p : pairs) {
    if (!p.parallel) continue;
    for (int order = 0; order < 2; ++order) {
      const Edge& e1 = edges[order == 0 ? p.first : p.second];
      const Edge& e2 = edges[order == 0 ? p.second : p.first];
      const Vec3& d = e1.direction;
      const Vec3 r12 = e2.start - e1.start;
      p.offset_m[order] = r12 - r12.dot(d) * d;
      p.offset_length_m[order] = p.offset_m[order].norm();
    }
  }
  return pairs;
}

}  // namespace rfidray
