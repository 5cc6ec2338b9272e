#pragma once
// Blocked segments found without an Embree ray, exactly: axis-aligned rectangles that the scene's triangles
// cover entirely, binned in a 2-D grid per axis.
//
// Why not solid-interior voxels: the parametric warehouses' occluders are 3 cm shelf plates (closed boxes
// made of six separately tessellated faces whose shared edges are not index-shared) and 8 cm posts open at
// the bottom; a voxel strictly inside them with a margin would have to be < 1.5 cm, billions of voxels for
// a 1 M-triangle warehouse. What those occluders do have is large flat faces, so the proxy here is the
// face, not the volume.
//
// Covered rectangle. Take the triangles lying exactly in one axis-aligned plane x_k = c (all three vertices'
// k-coordinate bitwise equal). As a mod-2 chain, their covering parity is constant off the edges that occur
// an odd number of times among them (edges welded by exact vertex position; a collinear T-junction counts as
// odd, which only makes this more conservative). So a rectangle R of that plane whose margin-inflated R⁺
// meets no odd edge, and one of whose interior points lies in an odd number of those triangles, is covered
// at every point by at least one triangle. R is found per grid cell and per connected set of triangles (cell
// ∩ the set's bounds, shrunk by 2 margins when that is needed to clear the odd edges).
//
// Certainty. blocks(o, d, tnear, tfar) is true only if the segment crosses some R transversally, at Q with
// |Q − R| = 0 and Q's distance along the ray inside [tnear, tfar] by more than Embree's float error. Embree
// (float vertices relative to Scene::local_origin) then reports a hit on a triangle covering Q, so `occluded`
// would return true: culling with blocks() changes the number of rays, never a result. Q may lie on an inner
// edge or vertex of a tessellated face; there the hit rests on RTC_SCENE_FLAG_ROBUST (raytrace/
// embree_scene.cpp): its Plücker edge functions of two neighbouring triangles are exact negatives of each
// other and vertices get a ulp·|U+V+W| tolerance — the property the exhaustive search's own legs rely on.
// tests/raytrace/test_covered_rects.cpp checks blocks() ⇒ occluded() on random segments, segments ending on
// surfaces, crossings next to rectangle edges and crossings exactly at inner vertices and edges. The float error allowed for is
// err = 1e-6·(M + |o − origin| + tfar) metres (M = the scene's largest coordinate magnitude about the local
// origin; ≥ 16 float ulps of every magnitude involved); across the plane it grows as err/|d_k|, so
// crossings flatter than that allows (|d_k| < err / (margin/2 − err)) are not decided here (false).
//
// Thread safety: immutable after construction; blocks() may be called from any number of threads.
// Construction throws only std::bad_alloc.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "core/geometry.h"
#include "raytrace/scene_mesh.h"

namespace rfidray {

// Segments culled by CoveredRects (no Embree ray) on the calling thread; credited to the caller like
// tl_rays_traced (raytraced_channel.cpp).
inline thread_local uint64_t tl_segments_culled = 0;

class CoveredRects {
 public:
  // From the scene's meshes (Scene::meshes(), float vertices about `origin` = Scene::local_origin).
  CoveredRects(std::span<const SceneMesh> meshes, const Vec3& origin);

  // True only if EmbreeScene::occluded(o, d, tnear, tfar) is certain to be true (header comment); `d` unit.
  bool blocks(const Vec3& o, const Vec3& d, double tnear, double tfar) const;

  // One covered rectangle: plane x_axis = c, [lo_u, hi_u] × [lo_v, hi_v] in axes u = (axis+1)%3, v = (axis+2)%3;
  // every point of it inflated by margin_m() lies on a triangle of the scene in that plane.
  struct Rect {
    int axis;
    double c, lo_u, hi_u, lo_v, hi_v;
  };
  std::vector<Rect> rects() const;  // all of them (for tests)
  size_t rect_count() const;
  size_t bytes() const;         // heap bytes held
  double margin_m() const { return margin_m_; }

 private:
  struct Entry {                 // R in cell: plane x_k = c (world), (u, v) bounds about the local origin,
                                 // rounded inwards to float
    double c;
    float u_lo, u_hi, v_lo, v_hi;
  };
  struct AxisGrid {
    int k = 2, u = 0, v = 1;
    int nu = 0, nv = 0;          // 0: no rectangle on this axis
    double u0 = 0, v0 = 0, h = 1, inv_h = 1;  // about the local origin
    std::vector<uint32_t> start; // CSR over cells (nu·nv + 1) into entries, entries ascending in c per cell
    std::vector<Entry> entries;
  };
  void build_axis(std::span<const SceneMesh> meshes, int k);
  bool blocks_axis(const AxisGrid& g, const Vec3& o, const Vec3& d, double ta, double tb, double slack) const;

  Vec3 origin_ = Vec3::Zero();
  double magnitude_m_ = 0.0;     // M
  double margin_m_ = 0.0;        // R⁺ = R inflated by this is covered
  std::array<AxisGrid, 3> grids_;
  std::array<int, 3> order_{2, 0, 1};  // axes tried first to last
};

}  // namespace rfidray
