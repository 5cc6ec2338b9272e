#pragma once
// Paths of one antenna–tag link in a static scene.
//
// Direct path. Unoccluded → `los`. Otherwise (level ≥ los+blocked) → `blocked`: the straight segment is kept
// and every surface it crosses multiplies the field by that surface's transmission (core/fresnel.h
// material_transmission: the ITU-R P.2040 slab of the material's thickness when it has one, else the single
// air→material interface), applied per TE/TM component with transmit_field. Each crossed triangle counts as
// one surface, so a wall should be modelled as one sheet carrying the wall's thickness (a closed box would be
// crossed twice). Metal (perfect conductor) is opaque: the path is dropped. No refraction offset.
//
// Single-bounce specular reflection, exact image method: the tag T is mirrored in the facet plane (T'),
// the reflection point P is where A→T' meets the plane, it must lie on the facet's triangles, and both legs
// A→P and P→T must be unoccluded. Length |A − T'|. Coefficient:
//   √(G_R(A→P) G_T(T→P)) · e_tag · R(e_A),
// with e_A the reader's field towards P (Polarization::field), R = reflect_field with material_reflection
// at the angle of incidence (TE ⊥ plane of incidence, TM in it; conventions in core/fresnel.h), and e_tag·
// the polarization match at the tag (core/polarization.h).
//
// Contribution of each path: path_contribution(L, coefficient, f) = coefficient·λ/(4πL)·e^{−jkL}.
// Paths more than drop_below_db below the strongest are dropped. Reflections are ordered by length, then facet.
#include <complex>
#include <memory>
#include <span>
#include <vector>

#include "core/channel.h"
#include "core/path.h"
#include "raytrace/scene.h"
#include "raytrace/trace_options.h"

namespace rfidray {

inline constexpr uint32_t kNoMaterial = std::numeric_limits<uint32_t>::max();

// A path as the tracer produces it (no strings: the hot loop does not allocate).
struct TracedPath {
  PathKind kind = PathKind::kLineOfSight;
  double length_m = 0.0;
  Vec3 point = Vec3::Zero();
  uint32_t material = kNoMaterial;  // reflecting or first crossed surface
  uint32_t facet = kNoFacet;        // reflecting facet
  int crossings = 0;
  std::complex<double> coefficient{1.0, 0.0};
  std::complex<double> contribution{0.0, 0.0};
};

// Where reflections can be for one antenna pose (the per-pose, tag-independent part of the candidate search).
// With candidate rays, a plane is tried only if a ray from the antenna hit it, and a reflection point only if
// it lies in a cell of that plane's occupancy grid that some ray's footprint covered (the region of the plane
// the antenna sees). Each surviving candidate is then made exact by the image method and both legs' rays.
struct PoseCandidates {
  bool all = true;                     // test every plane and every point (exact)
  std::vector<uint32_t> planes;        // otherwise only these (plane-group ids) ...
  std::vector<uint64_t> seen_cells;    // ... and only points in these cells (occupancy-grid bit indexing)
  std::vector<uint32_t> touched_words; // words of seen_cells set since the last clear
  std::vector<RayHit> hits;            // per-ray scratch
  std::vector<char> plane_seen;        // per-plane scratch
};

class PathFinder {
 public:
  PathFinder(std::shared_ptr<const Scene> scene, const TraceOptions& options);

  const Scene& scene() const { return *scene_; }
  const TraceOptions& options() const { return options_; }
  size_t plane_count() const { return planes_.size(); }

  // Per-pose candidate search (shoots options().candidate_rays rays when > 0 in fast mode).
  void prepare_pose(const Vec3& antenna_position, PoseCandidates& out) const;
  // Every path of one link into `out` (cleared first; reuse it across calls to avoid allocation).
  // Throws InputError if the endpoints coincide or are not finite.
  void trace(const Endpoint& antenna, const Endpoint& tag, double frequency_hz, const PoseCandidates& candidates,
             std::vector<TracedPath>& out) const;

  // Converts a traced path to the core Path (material names filled in).
  Path to_path(const TracedPath& p) const;

 private:
  // Facets sharing one plane (fast mode): one image per plane, Embree says which facet is hit.
  // A conservative occupancy bitmap over the plane (facet bounds rasterised, in the two world coordinates
  // the plane projects onto without degeneracy) rejects most image points with no facet near them before
  // any ray is shot.
  struct PlaneGroup {
    Vec3 normal;
    double offset_m;
    Vec3 lo, hi;
    double flatness_m = 0.0;  // max over its facets
    int axis_u = 0, axis_v = 1;
    double u0 = 0, v0 = 0, inv_du = 0, inv_dv = 0;
    int nu = 1, nv = 1;
    size_t bit_offset = 0;  // into occupancy_
  };
  // Bit index of p's cell in g's grid, or SIZE_MAX when p is outside the grid.
  size_t cell_bit(const PlaneGroup& g, const Vec3& p) const;
  // Marks the occupied cells of g under the footprint of a candidate ray (direction dir, footprint radius
  // radius_m across the ray) that hit at p as seen.
  void mark_seen(const PlaneGroup& g, const Vec3& p, const Vec3& dir, double radius_m, PoseCandidates& out) const;

  void direct_path(const Endpoint& a, const Endpoint& t, double f, std::vector<TracedPath>& out) const;
  void reflections_exhaustive(const Endpoint& a, const Endpoint& t, double f, std::vector<TracedPath>& out) const;
  void reflections_fast(const Endpoint& a, const Endpoint& t, double f, const PoseCandidates& c,
                        std::vector<TracedPath>& out) const;
  void try_plane(uint32_t group, const Endpoint& a, const Endpoint& t, double f, const PoseCandidates& c,
                 std::vector<TracedPath>& out) const;
  // Shared tail of both modes: P on facet f is valid; checks leg 2 (and leg 1 if asked) and appends.
  void add_reflection(uint32_t facet, const Vec3& image, const Vec3& p, const Endpoint& a, const Endpoint& t,
                      double f, bool check_leg1, std::vector<TracedPath>& out) const;
  bool point_on_facet(const Facet& facet, const Vec3& p) const;

  std::shared_ptr<const Scene> scene_;
  TraceOptions options_;
  double drop_power_ratio_ = 0.0;  // db_to_linear(-drop_below_db)
  double max_length2_ = 0.0;       // max_path_length_m²
  std::vector<PlaneGroup> planes_;
  std::vector<uint32_t> plane_of_facet_;
  std::vector<uint64_t> occupancy_;
  std::vector<Vec3> candidate_directions_;
  double candidate_spacing_rad_ = 0.0;  // angular spacing of the candidate rays, √(4π/N)
};

}  // namespace rfidray
