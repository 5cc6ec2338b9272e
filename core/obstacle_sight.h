#pragma once
// What a link sees beyond its nearest edge (core/edge_sight.h): the geometries that the canonical wedge check of
// core/level_validity.h does not cover and that the FDTD runs of bench/fullwave/ found the ray levels wrong in
// (docs/fullwave.md, "Other geometries"): a narrow obstacle on or beside the direct line (a rack upright), the
// direct line through a penetrable slab near the slab's edge (a concrete wall), an end between two facing parallel
// metal plates (a rack bay), an end behind a penetrable slab near its edge or opening (a doorway), a diffraction point near its edge's end (a plate's corner), a metal plate seen edge-on. Values: raytrace fills them from the scene (Channel::obstacle_sight), core judges
// them (core/level_validity.h). Units: metres.
#include <optional>

namespace rfidray {

// Two edges close together near one end of the link (or near where the direct segment is blocked): an object
// whose cross-section is a fraction of a wavelength, lying within the first Fresnel zone of the direct line.
// Rays treat it as an opaque screen with single-edge diffraction; the field behind it is neither that shadow nor
// the single-edge transition (behind a 5 cm post, FDTD finds 0.25–0.62 of the free-space field).
struct NarrowObstacle {
  double width_m = 0.0;           // distance between the two edges' points nearest to where it was seen
  double distance_m = 0.0;        // from the link's end (or the blocking point) to the nearer edge
  double clearance_m = 0.0;       // the direct segment's distance from the nearer edge (0 when it is blocked)
  double fresnel_radius_m = 0.0;  // first Fresnel zone radius √(λ d1 d2 / (d1 + d2)) where the segment passes it
  bool blocks = false;            // the direct segment is blocked by it
  bool at_end = true;             // seen from an end (else from the point where metal blocks the direct segment)
  // Both edges are a thin post's that the level models as a circular cylinder (raytrace/thin_posts.h: levels
  // full-selective and full): measured within 0.03–0.09 of FDTD behind and beside a 5 cm upright.
  bool modelled_post = false;
  // A modelled post within kρ = 4 of an end but off the direct line's Fresnel zone (beside or behind the tag): the
  // end is in the post's near field (rack_post.csv: 0.05–0.135 off beside a post whose shelves run through it).
  bool off_line = false;
};

// The direct segment's first obstacle is a penetrable (non-metal) surface: the link is a slab transmission
// (P.2040), which is exact for an infinite slab; the slab's nearest edge to the crossing point diffracts a field
// of ~0.225/ν of the free-space one (knife edge, ITU-R P.526-15 §4.1 for ν > 1), where
// ν = h·√(2 (d1 + d2) / (λ d1 d2)), h the edge's distance from the crossing point.
struct SlabCrossing {
  double edge_distance_m = 0.0;  // crossing point to the slab's nearest edge (its facet's border when no edge is
                                 // indexed that close)
  double fresnel_nu = 0.0;       // ν of that edge
};

// An end on the far side of a penetrable slab's plane from the other end, with the slab's edge (an outline or an
// opening's jamb) within the edge index's reach: every level models the slab as a zero-thickness sheet with a
// transmission coefficient, and the field that passes a thick slab's edge or opening (a doorway) is neither that
// nor UTD with heuristic coefficients.
struct PenetrableEdge {
  double distance_m = 0.0;  // the end's distance from the edge
};

// An end between two facing parallel metal plates (a shelf bay): multiple bounces between the plates and the
// plates' edges both matter; rays with first-order UTD were measured 0.14–0.19 (median) off between two plates
// 0.4 m apart and 0.12 off just in front of them, with second-order diffraction between the edges 0.05 and 0.07.
struct ParallelPlates {
  double gap_m = 0.0;     // distance between the two plates' planes
  bool inside = false;    // the end faces both plates (its perpendicular foot lies on each); else in front of them
  // The channel diffracts twice between edges this far apart (TraceOptions::double_diffraction_max_m ≥ gap_m): the
  // diffracting levels' measured error is then the second-order one.
  bool second_order_diffraction = false;
};

// A first-order diffraction point near its edge's end (a plate's corner, the end of a shelf's lip): the diffracting
// levels compute each edge's term as if the edge were infinite and drop it once its Keller point leaves the edge,
// so the field jumps there by the whole term (0.91 of the free-space field beside a 0.6 m plate's corner,
// docs/fullwave.md, "Where `full` is discontinuous"). What the edge integral carries instead is its stationary
// value weighted by the share T of the Fresnel zone that lies on the edge (½ with the point at an end, → 1 deep
// inside, → 0 far past it: the uniform endpoint evaluation of the edge integral); the estimate is the term's share
// of the free-space field times |step − T|, step the level's 1 on the edge and 0 off it.
struct EdgeEnd {
  double past_end_m = 0.0;            // the Keller point's distance past the nearer end (negative: on the edge)
  double fresnel_half_width_m = 0.0;  // the edge's first Fresnel zone half-width along it, √(λ s s'/(s + s'))/sin β₀
  double term_share = 0.0;            // the infinite edge's term there, a fraction of the free-space field
  double estimated_error = 0.0;       // term_share · |step − T| (see above)
};

// A metal plate seen edge-on: two roughly parallel edges of one facet both within the direct line's first Fresnel
// zone, λ/2 or more apart along the line but less than λ/2 apart across it (the line within a few degrees of the
// plate's plane: a shelf seen at grazing). Rays see two opaque half-planes there (the direct ray blocked or grazing,
// each edge's full UTD term); FDTD finds such a plate nearly invisible with E normal to it (|E/E₀| 0.97–1.0 beyond
// a 0.6 m and a 1.8 m wide plate seen 3.4° from its plane; docs/fullwave.md).
struct EdgeOnPlate {
  double along_m = 0.0;           // the two edges' separation along the direct line
  double across_m = 0.0;          // and across it
  double clearance_m = 0.0;       // the farther of the two edges' distances from the direct segment
  double fresnel_radius_m = 0.0;  // the first Fresnel zone radius where that edge passes
};

struct ObstacleSight {
  std::optional<NarrowObstacle> narrow;
  std::optional<SlabCrossing> slab;
  std::optional<PenetrableEdge> beyond_slab_edge;
  std::optional<ParallelPlates> plates;
  std::optional<EdgeEnd> edge_end;  // the link's most uncertain edge end, when its estimate is ≥ kEdgeEndReported
  std::optional<EdgeOnPlate> edge_on_plate;
};

// Below this estimate (a fraction of the free-space field) an edge end is not reported.
inline constexpr double kEdgeEndReported = 0.05;

}  // namespace rfidray
