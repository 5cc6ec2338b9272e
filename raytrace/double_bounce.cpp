// Level double-bounce: every specular path with two reflections, by the image of the image
// (raytrace/path_finder.h has the physics). Both candidate modes walk every ordered pair of distinct planes:
//  - exact: the occupancy bitmaps reject points with no facet near them, then one closest-hit ray per leg says
//    which facet is at P1 (the ray A→P1) and at P2 (the ray P1→P2) and that the leg is clear;
//  - exhaustive: the points are tested against every facet of their plane (point in triangle) and every leg
//    by an occlusion ray. Both give the same paths (tests/raytrace/test_double_bounce.cpp).
#include <cmath>

#include "core/fresnel.h"
#include "core/units.h"
#include "raytrace/image_geometry.h"
#include "raytrace/path_finder.h"

namespace rfidray {

void PathFinder::double_reflections(const Endpoint& ant, const Endpoint& tag, double f, const PoseCandidates& c,
                                    double floor, std::vector<TracedPath>& out) const {
  const auto n = static_cast<uint32_t>(planes_.size());
  for (uint32_t g2 = 0; g2 < n; ++g2)
    for (uint32_t g1 = 0; g1 < n; ++g1)
      if (g1 != g2) try_plane_pair(g1, g2, ant, tag, f, c, floor, out);
}

void PathFinder::try_plane_pair(uint32_t g1, uint32_t g2, const Endpoint& ant, const Endpoint& tag, double f,
                                const PoseCandidates& c, double floor, std::vector<TracedPath>& out) const {
  const PlaneGroup& a_plane = planes_[g1];
  const PlaneGroup& b_plane = planes_[g2];
  const Vec3& a = ant.pose.position;
  const Vec3& t = tag.pose.position;
  const double eps = options_.surface_epsilon_m;
  // T2: the tag's image in plane 2. T21: T2's image in plane 1; P1 on plane 1 between A and T21.
  const double dt2 = b_plane.normal.dot(t) - b_plane.offset_m;
  if (std::abs(dt2) < eps) return;
  const Vec3 t2 = t - 2.0 * dt2 * b_plane.normal;
  Vec3 t21, p1, t2_again, p2;
  if (!image_point(a_plane.normal, a_plane.offset_m, a, t2, eps, t21, p1)) return;
  if ((t21 - a).squaredNorm() > max_length2_) return;
  // P2 on plane 2 between P1 and T2 (P1 and T strictly on one side of plane 2).
  if (!image_point(b_plane.normal, b_plane.offset_m, p1, t, eps, t2_again, p2)) return;
  const bool exhaustive = options_.candidates == CandidateMode::kExhaustive;
  // Cheap rejections first: no facet near P1 or P2 (the occupancy grids, conservative).
  const size_t bit1 = cell_bit(a_plane, p1), bit2 = cell_bit(b_plane, p2);
  if (bit1 == SIZE_MAX || bit2 == SIZE_MAX) return;
  if (!((occupancy_[bit2 / 64] >> (bit2 % 64)) & 1u)) return;
  if (c.all || exhaustive) {
    if (!((occupancy_[bit1 / 64] >> (bit1 % 64)) & 1u)) return;
  } else if (!((c.seen_cells[bit1 / 64] >> (bit1 % 64)) & 1u)) {
    return;  // P1 not seen from the antenna by the candidate rays
  }
  const double length = (t21 - a).norm();
  const Vec3 dir1 = (p1 - a).normalized(), dir3 = (t - p2).normalized();
  const double gain = std::sqrt(ant.pattern.gain_linear_world(ant.pose.orientation, dir1) *
                                tag.pattern.gain_linear_world(tag.pose.orientation, -dir3));
  // |Γ| ≤ 1 at each bounce and a polarization match ≤ 1: an upper bound of the contribution. Below the drop
  // floor the path would be dropped anyway: no ray for it.
  const double bound = gain * wavelength_m(f) / (4.0 * kPi * length);
  if (bound * bound < floor) return;

  const EmbreeScene& bvh = scene_->bvh();
  const auto& facets = scene_->facets();
  uint32_t f1 = kNoFacet, f2 = kNoFacet;
  const double l1 = (p1 - a).norm(), l2 = (p2 - p1).norm();
  if (!(l1 > 0.0) || !(l2 > 0.0)) return;
  const Vec3 dir2 = (p2 - p1) / l2;
  if (exhaustive) {
    for (uint32_t m : plane_members_[g1])
      if (point_on_facet(facets[m], p1)) {
        f1 = m;
        break;
      }
    for (uint32_t m : plane_members_[g2])
      if (point_on_facet(facets[m], p2)) {
        f2 = m;
        break;
      }
    if (f1 == kNoFacet || f2 == kNoFacet) return;
  } else {
    // The first thing on A→P1 must be a facet of plane 1, the first thing on P1→P2 one of plane 2.
    const double m1 = plane_margin(eps + a_plane.flatness_m, std::abs(dir1.dot(a_plane.normal)), l1);
    const RayHit h1 = bvh.intersect(a, dir1, std::min(options_.endpoint_epsilon_m, 0.25 * l1), l1 + m1);
    if (!h1.hit) return;
    f1 = scene_->facet_of(scene_->triangle_id(h1.geom, h1.prim));
    if (f1 == kNoFacet || plane_of_facet_[f1] != g1) return;
    const double start = plane_margin(eps + a_plane.flatness_m, std::abs(dir2.dot(a_plane.normal)), l2);
    const double m2 = plane_margin(eps + b_plane.flatness_m, std::abs(dir2.dot(b_plane.normal)), l2);
    const RayHit h2 = bvh.intersect(p1, dir2, start, l2 + m2);
    if (!h2.hit) return;
    f2 = scene_->facet_of(scene_->triangle_id(h2.geom, h2.prim));
    if (f2 == kNoFacet || plane_of_facet_[f2] != g2) return;
  }
  // Redo the images in the facets' own planes (identical to the groups' within the grouping tolerance).
  const Facet& fa = facets[f1];
  const Facet& fb = facets[f2];
  const double dt = fb.signed_distance(t);
  if (std::abs(dt) < eps) return;
  const Vec3 t2f = t - 2.0 * dt * fb.normal;
  if (!image_point(fa.normal, fa.offset_m, a, t2f, eps, t21, p1)) return;
  if (!image_point(fb.normal, fb.offset_m, p1, t, eps, t2_again, p2)) return;
  const Vec3 d1 = p1 - a, d2 = p2 - p1, d3 = t - p2;
  const double len1 = d1.norm(), len2 = d2.norm(), len3 = d3.norm();
  if (!(len1 > 0.0) || !(len2 > 0.0) || !(len3 > 0.0)) return;
  const Vec3 u1 = d1 / len1, u2 = d2 / len2, u3 = d3 / len3;
  const double cos1 = std::abs(u1.dot(fa.normal)), cos2 = std::abs(u2.dot(fb.normal));
  const double clear1 = eps + fa.flatness_m, clear2 = eps + fb.flatness_m;
  const double end1 = std::min(options_.endpoint_epsilon_m, 0.25 * len1);
  const double end3 = std::min(options_.endpoint_epsilon_m, 0.25 * len3);
  if (exhaustive) {
    // From the facet back to the antenna: precision is needed next to the facet (path_finder.cpp, leg 1).
    if (bvh.occluded(p1, -u1, plane_margin(clear1, cos1, len1), len1 - end1)) return;
    if (bvh.occluded(p1, u2, plane_margin(clear1, cos1, len2), len2 - plane_margin(clear2, cos2, len2))) return;
  }
  if (bvh.occluded(p2, u3, plane_margin(clear2, cos2, len3), len3 - end3)) return;

  const CVec3 e0 = ant.polarization.field(ant.pose.orientation, u1);
  const CVec3 e1 = reflect_field(e0, u1, fa.normal, material_reflection(scene_->materials()[fa.material], f, cos1));
  const CVec3 e2 = reflect_field(e1, u2, fb.normal, material_reflection(scene_->materials()[fb.material], f, cos2));
  const double g = std::sqrt(ant.pattern.gain_linear_world(ant.pose.orientation, u1) *
                             tag.pattern.gain_linear_world(tag.pose.orientation, -u3));
  TracedPath path;
  path.kind = PathKind::kReflection2;
  path.length_m = (t21 - a).norm();
  path.point = p1;
  path.material = fa.material;
  path.facet = f1;
  path.point2 = p2;
  path.material2 = fb.material;
  path.facet2 = f2;
  path.coefficient = g * polarization_match(e2, tag.polarization, tag.pose.orientation, u3);
  path.contribution = path_contribution(path.length_m, path.coefficient, f);
  out.push_back(path);
}

}  // namespace rfidray
