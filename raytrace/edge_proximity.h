#pragma once
// How far a point is from the nearest diffracting edge of a scene (raytrace/edges.h): what decides whether ray
// optics and UTD can be trusted at a link's ends (core/level_validity.h). Only distances up to a fixed radius are
// answered; beyond it "none that close".
//
// A uniform hash grid of cell size 2·radius holds points sampled along each edge every `radius`; a query looks at
// its cell and the 26 around it and measures the exact point–segment distance to each edge found. Any edge within
// `radius` of the point has a sample within 1.5·radius, so inside that neighbourhood: the query is exact.
//
// Units: metres. Thread-safe after construction (queries only read). Memory: one entry per sample, about
// (total edge length / radius + edges) entries.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <unordered_map>
#include <vector>

#include "core/geometry.h"
#include "raytrace/edges.h"

namespace rfidray {

class EdgeProximity {
 public:
  // Throws std::invalid_argument for a radius that is not finite and > 0.
  EdgeProximity(const std::vector<Edge>& edges, double radius_m);

  struct Hit {
    uint32_t edge = kNoEdge;  // index into the edges given to the constructor
    double distance_m = 0.0;
  };
  // The nearest edge within the radius, and the second nearest other edge within it (edge == kNoEdge where
  // there is none). Does not allocate.
  std::array<Hit, 2> nearest_two(const Vec3& point) const;
  // The nearest best.size() edges within the radius, nearest first (edge == kNoEdge past the last found; ties go
  // to the lower index). Where several edges meet (a box's corner: three, and a thin box's far face just beyond)
  // the two nearest may both be edges the link's ends do not see alike. Does not allocate.
  void nearest(const Vec3& point, std::span<Hit> best) const;
  // Distance (m) from `point` to the nearest edge, when one is within the radius.
  std::optional<double> nearest_m(const Vec3& point) const;
  // Every edge with a point within `distance_m` of the segment [a, b], and possibly others (the caller measures),
  // into `out`, ascending, without repeats: the cells within distance_m + radius/2 of the segment (each edge has a
  // sample every radius along it). When that is more than a million cells, every edge. Clears `out` first.
  void edges_near_segment(const Vec3& a, const Vec3& b, double distance_m, std::vector<uint32_t>& out) const;
  const Edge& edge(uint32_t i) const { return edges_[i]; }
  double radius_m() const { return radius_m_; }
  size_t edges() const { return edges_.size(); }

 private:
  static uint64_t key(int64_t i, int64_t j, int64_t k);
  std::vector<Edge> edges_;
  double radius_m_ = 0.0, cell_m_ = 0.0;
  std::unordered_map<uint64_t, std::vector<uint32_t>> cells_;
};

}  // namespace rfidray
