#pragma once
// Pairs of edges near each other: the second-order diffraction of levels full-selective and full
// (raytrace/double_diffraction.cpp) follows a path from the antenna to one edge, on to the other, then to the tag.
// Two kinds: parallel edges (a shelf plate's front and back edges, the two plates of a bay, a wall's faces), whose
// two diffraction points are in closed form, and any two edges of one facet (a plate's side edge and its back edge),
// whose leg between them grazes that facet.
// Thread safety: values only.
#include <cstdint>
#include <span>
#include <vector>

#include "raytrace/edges.h"
#include "raytrace/facet.h"

namespace rfidray {

struct EdgePair {
  uint32_t first = 0, second = 0;  // indices into the edge list, first < second; the tracer takes both orders
  // A facet that both edges bound and that lies between them: the leg from one edge to the other runs along
  // it, grazing (the edges of one shelf plate). kNoFacet when the leg crosses free space.
  uint32_t shared_facet = kNoFacet;
  double distance_m = 0.0;  // parallel: between the two edges' lines; else between the two segments
  bool parallel = true;
  // Parallel pairs, per order of the tracer (0: first then second; 1: second then first): the offset of the other
  // edge's line from the first-taken edge's, ⟂ that edge (from its start to the other's start, minus the part
  // along it), and its length. The same arithmetic the tracer would do per link, done once.
  Vec3 offset_m[2] = {Vec3::Zero(), Vec3::Zero()};
  double offset_length_m[2] = {0.0, 0.0};
};

// The facet of edge e that the direction `u` (unit, ⟂ the edge) points into from the edge, or kNoFacet.
uint32_t facet_towards(const Edge& e, const Vec3& u);

// Every pair of parallel edges (directions within 1e-6 rad, either sense) whose lines are at most `max_distance_m`
// and more than 1e-6 m apart and whose extents along them are at most `max_distance_m` apart, and every pair of
// other edges bounding a common facet whose segments are at most `max_distance_m` apart (edges meeting at a corner
// are 0 apart); edges with `skip[i] != 0` (thin posts' edges) take part in none. Sorted by (first, second):
// deterministic.
std::vector<EdgePair> find_edge_pairs(std::span<const Edge> edges, std::span<const uint8_t> skip,
                                      double max_distance_m);

}  // namespace rfidray
