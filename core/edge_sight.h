#pragma once
// How one end of a link sees the nearest diffracting edge of the scene, lit from the other end: the canonical
// wedge problem of core/wedge_series.h placed at that end (core/level_validity.h judges a level by it). A value:
// raytrace fills it from the scene's edges (Channel::nearest_edge).
#include <optional>

namespace rfidray {

// The nearest edge as one end of a link sees it, lit from the other end (raytrace fills it from the scene).
struct EdgeSight {
  double distance_m = 0.0;        // this end's distance from the edge's line
  double n = 2.0;                 // exterior angle / π (2: a sheet's free edge, 1.5: a right-angled wedge)
  double phi_rad = 0.0;           // this end's angle about the edge from face 0 (core/utd.h)
  double phi_prime_rad = 0.0;     // the other end's
  double sin_beta0 = 1.0;         // sine of the angle between the incident ray and the edge
  double other_distance_m = 0.0;  // the other end's distance from the edge's line
  bool metal_faces = true;        // both faces perfect conductors
  // |E^i·β̂0'| / |E^i| of the incident field at the edge: its share along the edge's soft direction (core/utd.h);
  // the rest, √(1 − share²), is the hard part (E ⊥ edge), whose near field no ray level has.
  double soft_share = 1.0;
  // |p̂·ê_s| of this end's antenna (p̂ its unit axis, or its polarization's field for a non-linear one): how much of
  // the edge's singular near field it reads. Across the edge that field is E ∝ (kρ)^{1/n − 1}·ê_s with
  // ê_s = sin(φ/n) ρ̂ + cos(φ/n) φ̂ (Meixner's edge condition; φ̂ the direction of growing φ): along ρ̂ on the
  // wedge's bisector, normal to each face on it. 1 when the axis lies along it, 0 along the edge.
  double singular_share = 1.0;
  std::optional<double> second_edge_m;  // another edge within reach of this end, when there is one
};

}  // namespace rfidray
