#pragma once
// Diffracting edges of a scene, extracted from its merged facets (raytrace/facet.h) for first-order UTD
// (core/utd.h, used by the path finder at level `full`).
//
// An edge is a straight piece of a facet's outline (a triangle edge used once inside its facet, vertices
// welded across all meshes on a 1 µm grid), merged with its collinear neighbours into maximal segments:
//  - shared by two facets that are not coplanar: a wedge. Its two faces split the space around the edge into
//    two angular regions, α (from face a to face b, turning about +direction) and 2π − α; at trace time the
//    region holding both antenna and tag is the wedge's exterior (exterior angle nπ). A closed solid's inside
//    region is never lit (its legs are occluded), so face normals need not be oriented consistently.
//  - used by one facet only, and lying on no other facet: the free edge of a sheet, a half-plane (n = 2).
//    A sheet that ends on another surface (a post standing on the floor) is a junction, not an edge.
//  - edges inside a flat facet, between coplanar facets, or shared by more than two facets: none.
// Thread safety: values only.
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/geometry.h"
#include "core/units.h"

namespace rfidray {

class Scene;

inline constexpr uint32_t kNoEdge = std::numeric_limits<uint32_t>::max();

struct Edge {
  Vec3 start = Vec3::Zero();
  Vec3 direction = Vec3::UnitZ();  // unit, along the edge
  double length_m = 0.0;
  uint32_t facet_a = 0;
  uint32_t facet_b = std::numeric_limits<uint32_t>::max();  // kNoFacet for a half-plane
  // Unit vectors in face a (b), perpendicular to the edge, pointing from the edge into the face.
  Vec3 into_a = Vec3::UnitX(), into_b = Vec3::UnitX();
  // Angle from into_a to into_b turning about +direction, in (0, 2π); 2π for a half-plane.
  double alpha_rad = 0.0;

  bool half_plane() const { return facet_b == std::numeric_limits<uint32_t>::max(); }
};

struct EdgeOptions {
  double flat_tolerance_rad = 1e-3;  // faces closer than this to coplanar make no edge
  double junction_tolerance_m = 1e-5;  // a free edge within this of another facet is a junction
};

// The edge-fixed angles of core/utd.h for a source and an observer off the edge's line, from their components
// perpendicular to the edge (`v_source`, `v_observer`, measured from a point of the edge): which exterior region
// holds both (a half-plane's whole plane; a wedge's side α or 2π − α), its n, both angles from that region's
// face 0, and the facets that are face 0 and face n. False when the faces separate the two points or the region
// is not convex (n ≤ 1: no edge seen from that side). Inline: the diffraction loop calls it per edge and link.
struct WedgeAngles {
  double n = 2.0;
  double phi_prime_rad = 0.0;  // the source's angle
  double phi_rad = 0.0;        // the observer's angle
  uint32_t face0 = 0, facen = 0;
};

// Angle of v (⟂ the edge) about +e measured from `from`, in [0, 2π).
inline double angle_about(const Vec3& v, const Vec3& e, const Vec3& from) {
  double a = std::atan2(v.dot(e.cross(from)), v.dot(from));
  if (a < 0.0) a += kTwoPi;
  return a;
}

inline bool wedge_angles(const Edge& e, const Vec3& v_source, const Vec3& v_observer, WedgeAngles& out) {
  const double psi_a = angle_about(v_source, e.direction, e.into_a);
  const double psi_t = angle_about(v_observer, e.direction, e.into_a);
  out.face0 = out.facen = e.facet_a;
  if (e.half_plane()) {
    out.n = 2.0;
    out.phi_prime_rad = psi_a;
    out.phi_rad = psi_t;
  } else if (psi_a < e.alpha_rad && psi_t < e.alpha_rad) {
    out.n = e.alpha_rad / kPi;
    out.phi_prime_rad = psi_a;
    out.phi_rad = psi_t;
    out.facen = e.facet_b;
  } else if (psi_a > e.alpha_rad && psi_t > e.alpha_rad) {
    out.n = (2.0 * kPi - e.alpha_rad) / kPi;
    out.phi_prime_rad = psi_a - e.alpha_rad;
    out.phi_rad = psi_t - e.alpha_rad;
    out.face0 = e.facet_b;
  } else {
    return false;  // the faces separate source and observer
  }
  return out.n > 1.0 + 1e-9;  // concave or flat: no convex edge seen from this side
}

// All edges of the scene, in a deterministic order.
std::vector<Edge> extract_edges(const Scene& scene, const EdgeOptions& options = {});

}  // namespace rfidray
