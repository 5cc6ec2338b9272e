#pragma once
// Thin metal posts of a scene (rack uprights, pillars of a guard rail, poles), found once from its edges, for
// levels `full-selective` and `full` to treat as what they are at UHF: sub-wavelength scatterers, not shadows.
// Behind a 5 cm post every ray level gives nothing (no ray gets there: the back edges are lit only at grazing
// incidence); FDTD gives 0.25–0.63 of free space 5–30 cm behind it (docs/fullwave.md, "Behind a rack upright").
// raytrace/post_scattering.cpp puts the exact scattering of a circular cylinder in their place.
//
// A post is a set of parallel edges (raytrace/edges.h) joined through the faces between them, all faces of
// perfectly conducting material and parallel to the edges (the sides), whose cross-section — the convex hull of
// the sides' vertices seen along the edges — is at most `max_width_m` across, at least 4 times shorter than
// the post is long, and compact (area ≥ 0.2 width²): a box post (4 edges) or a closed profile. Not a strip or an
// angle: across its axis a flat cross-section scatters by its orientation, which the equivalent circle has not. Its equivalent circular cylinder has the logarithmic capacity of that cross-section as its
// radius (core/logarithmic_capacity.h; 0.59 × the side of a square post), on the axis through the
// cross-section's centroid. The post's facets are its sides and the caps that close its ends inside the
// cross-section; its edges are the edges between its facets (and their free edges).
// Values only; find_thin_posts is a pure function of the scene and its edges.
#include <cstdint>
#include <limits>
#include <vector>

#include "core/geometry.h"
#include "raytrace/edges.h"

namespace rfidray {

class Scene;

inline constexpr uint32_t kNoPost = std::numeric_limits<uint32_t>::max();

struct ThinPost {
  Vec3 base = Vec3::Zero();          // on the axis, at the post's lower end (axis coordinate 0)
  Vec3 direction = Vec3::UnitZ();    // unit, along the axis
  double length_m = 0.0;
  double radius_m = 0.0;             // of the equivalent circular cylinder
  double width_m = 0.0;              // largest dimension of the cross-section
  uint32_t material = 0;             // its sides' (a perfect conductor)
};

struct ThinPosts {
  std::vector<ThinPost> posts;
  std::vector<uint32_t> post_of_facet;  // facet → its post, or kNoPost
  std::vector<uint32_t> post_of_edge;   // edge → its post, or kNoPost
};

// Every thin post, in a deterministic order (by its first edge). Empty tables when max_width_m ≤ 0.
ThinPosts find_thin_posts(const Scene& scene, const std::vector<Edge>& edges, double max_width_m);

}  // namespace rfidray
