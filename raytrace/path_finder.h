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
// Double bounce (level double-bounce, raytrace/double_bounce.cpp): A → P1 (plane 1) → P2 (plane 2) → T by the
// image of the image: T2 = T mirrored in plane 2, T21 = T2 mirrored in plane 1; P1 is where A→T21 meets plane
// 1, P2 where P1→T2 meets plane 2; both must lie on their facets, A and P2 on one side of plane 1, P1 and T on
// one side of plane 2, and all three legs unoccluded. Length |A − T21|. Coefficient
//   √(G_R(A→P1) G_T(T→P2)) · e_tag · R2(R1(e_A)),
// each reflection with its own Fresnel TE/TM in its own plane of incidence (reflect_field).
//
// Edge diffraction (level full, raytrace/diffraction.cpp): first-order UTD (core/utd.h) at every edge of
// raytrace/edges.h. The diffraction point Q is the Fermat point on the edge (the unfolded path is straight:
// Q divides the edge between the feet of A and T in the ratio of their distances from the edge); it must lie
// on the edge, A and T in the same exterior region of the wedge (exterior angle nπ, n > 1: convex wedges and
// half-planes; concave corners are left to the reflections, for n = 1/2 UTD's D vanishes exactly), both legs
// unoccluded. Length s' + s; coefficient √(G_R(ŝ') G_T(−ŝ)) · e_tag · [−D_s (e_A·β̂0')β̂0 − D_h (e_A·φ̂')φ̂]
// · √((s + s')/(s s')), which with the λ/(4π(s + s')) e^{−jk(s+s')} of path_contribution is KP's spherical-wave
// diffracted field. Faces of metal give KP's coefficients, other faces Luebbers' heuristic.
//
// Thin posts (levels full-selective and full, raytrace/post_scattering.cpp): a metal post at most
// TraceOptions::thin_post_max_width_m across (raytrace/thin_posts.h) is a conducting circular cylinder: one path of
// kind `post` per post, the exact 2-D series mapped to 3-D by stationary phase along its axis; its faces reflect
// nothing, its edges diffract nothing, and the direct path (and other posts' legs) pass through it.
//
// Contribution of each path: path_contribution(L, coefficient, f) = coefficient·λ/(4πL)·e^{−jkL}.
// Paths more than drop_below_db below the strongest are dropped (a double reflection or a diffraction whose
// contribution, or an upper bound of it, is already below that floor is not traced further: it would be
// dropped). Order: direct path, reflections by length then facet, double reflections by length then facets,
// posts by length then post, diffractions by length then edge.
#include <array>
#include <complex>
#include <memory>
#include <span>
#include <vector>

#include "core/channel.h"
#include "core/path.h"
#include "raytrace/covered_rects.h"
#include "raytrace/edge_pairs.h"
#include "raytrace/edges.h"
#include "raytrace/scene.h"
#include "raytrace/thin_posts.h"
#include "raytrace/trace_options.h"

namespace rfidray {

inline constexpr uint32_t kNoMaterial = std::numeric_limits<uint32_t>::max();

// Single reflections on the calling thread, credited to the caller like tl_rays_traced
// (raytraced_channel.cpp): mirror points that lie on a facet and so need a visibility decision (one or two
// legs, by ray or by culling), and of those the reflections found (both legs clear). What the benchmarks
// report per link: the rays an exact search must spend follow from the first, the paths from the second.
inline thread_local uint64_t tl_mirror_points = 0;
inline thread_local uint64_t tl_reflections_found = 0;
// Double reflections on the calling thread: ordered plane pairs whose two reflection points were computed
// (try_plane_pair calls), credited likewise. Every pair per link without sharing; what plane_pairs_near
// keeps when links are traced together.
inline thread_local uint64_t tl_plane_pairs_tried = 0;
// Second-order diffraction on the calling thread: orders of edge pairs (a pair taken edge 1 first, or edge 2) that
// the per-link loop visited, credited likewise. Two per pair per link without sharing; what edge_pairs_near keeps
// when links are traced together.
inline thread_local uint64_t tl_edge_pair_orders_tried = 0;

// A path as the tracer produces it (no strings: the hot loop does not allocate).
struct TracedPath {
  PathKind kind = PathKind::kLineOfSight;
  double length_m = 0.0;
  Vec3 point = Vec3::Zero();
  uint32_t material = kNoMaterial;  // reflecting or first crossed surface (diffraction: face 0's)
  uint32_t facet = kNoFacet;        // reflecting facet (reflection2: the first)
  Vec3 point2 = Vec3::Zero();       // reflection2: the second reflection point; diffraction2: the second edge's
  uint32_t material2 = kNoMaterial;
  uint32_t facet2 = kNoFacet;
  uint32_t edge = kNoEdge;          // diffraction: index into PathFinder::edges() (diffraction2: the first edge)
  uint32_t edge2 = kNoEdge;         // diffraction2: the second edge
  uint32_t post = kNoPost;          // post: index into PathFinder::posts()
  int crossings = 0;
  std::complex<double> coefficient{1.0, 0.0};
  std::complex<double> contribution{0.0, 0.0};
};

// Where reflections can be for one antenna pose (the per-pose, tag-independent part of the candidate search).
// With candidate rays, a plane is tried only if a ray from the antenna hit it, and a reflection point only if
// it lies in a cell of that plane's occupancy grid that some ray's footprint covered (the region of the plane
// the antenna sees). Each surviving candidate is then made exact by the image method and both legs' rays.
// An ordered pair of plane groups (first reflection, second reflection) of the double-bounce search.
struct PlanePair {
  uint32_t first = 0, second = 0;
};

// The second-order diffraction work of a block of nearby tags (PathFinder::edge_pairs_near): the orders of edge pairs
// (2·pair + order, ascending) that can carry a path for some tag of the block, and the paired edges and pair corners
// those orders read (ascending). Per-thread scratch of trace_sum.
struct EdgePairBlock {
  std::vector<uint32_t> orders;
  std::vector<uint32_t> edges;
  std::vector<uint32_t> corners;
};

struct PoseCandidates {
  bool all = true;                     // test every plane and every point (exact)
  std::vector<uint32_t> planes;        // otherwise only these (plane-group ids) ...
  std::vector<uint64_t> seen_cells;    // ... and only points in these cells (occupancy-grid bit indexing)
  std::vector<uint32_t> touched_words; // words of seen_cells set since the last clear
  std::vector<RayHit> hits;            // per-ray scratch
  std::vector<char> plane_seen;        // per-plane scratch
  bool share_plane_pairs = false;      // trace_sum shares double-bounce plane pairs per block (see there)
  bool share_edge_pairs = false;       // trace_sum shares second-order diffraction's edge pairs per block
};

class PathFinder {
 public:
  PathFinder(std::shared_ptr<const Scene> scene, const TraceOptions& options);

  const Scene& scene() const { return *scene_; }
  const TraceOptions& options() const { return options_; }
  size_t plane_count() const { return planes_.size(); }
  // The diffracting edges (extracted at level full only, else empty).
  const std::vector<Edge>& edges() const { return edges_; }
  // The thin posts (raytrace/thin_posts.h) modelled as cylinders at levels full-selective and full (else empty).
  const std::vector<ThinPost>& posts() const { return posts_.posts; }
  // Per edge of edges(), its post or kNoPost (empty below full-selective).
  std::span<const uint32_t> post_of_edge() const { return posts_.post_of_edge; }

  // Per-pose candidate search (shoots options().candidate_rays rays when > 0 in exact mode).
  void prepare_pose(const Vec3& antenna_position, PoseCandidates& out) const;
  // Sets out.share_plane_pairs for the links from `antenna_position` to tags[order[…]] traced together
  // (TraceOptions::plane_pair_sharing; kAuto: finds the first block's pairs and shares when fewer than 0.42
  // of all ordered pairs are kept, with ≥ 64 tags: a block's pairs cost about nine per-link pair tests per
  // pair, saved on its 16 links for each pair pruned).
  void decide_plane_pair_sharing(const Vec3& antenna_position, std::span<const Endpoint> tags,
                                 std::span<const uint32_t> order, PoseCandidates& out) const;
  // Sets out.share_edge_pairs likewise for second-order diffraction (TraceOptions::edge_pair_sharing; kAuto: finds
  // the first block's orders and shares when fewer than 0.3 of them are kept, with ≥ 64 tags).
  void decide_edge_pair_sharing(const Vec3& antenna_position, std::span<const Endpoint> tags,
                                std::span<const uint32_t> order, PoseCandidates& out) const;
  // Every path of one link into `out` (cleared first; reuse it across calls to avoid allocation).
  // Throws InputError if the endpoints coincide or are not finite.
  void trace(const Endpoint& antenna, const Endpoint& tag, double frequency_hz, const PoseCandidates& candidates,
             std::vector<TracedPath>& out) const;

  // The links antenna→tags[k] for k in `which`, in that order: h[k] = Σ contributions of trace()'s paths
  // (what trace() gives). At level los the visibility rays are traced `packet_width` at a time (1, 4, 8 or
  // 16: EmbreeScene::occluded_many), except segments parallel to a coordinate plane, traced alone; the same
  // booleans as single rays but on near-degenerate rays (raytrace/embree_scene.h). Serial; thread-safe.
  // Throws what trace() throws (InputError for coincident or non-finite endpoints, bad frequency).
  void trace_sum(const Endpoint& antenna, std::span<const Endpoint> tags, std::span<const uint32_t> which,
                 double frequency_hz, const PoseCandidates& candidates, int packet_width,
                 std::span<std::complex<double>> h) const;
  // The level-los visibility segment of a link (direct_path's ray); false if the link is longer than
  // max_path_length_m (no path, no ray). *length_m (if given) = |tag − antenna|.
  bool direct_segment(const Vec3& antenna, const Vec3& tag, Segment& s, double* length_m = nullptr) const;

  // The covered rectangles that cull reflection legs (TraceOptions::cull_covered; null when off, in exhaustive
  // mode, or below level single-bounce) and the seconds their construction took.
  const CoveredRects* covered_rects() const { return covered_.get(); }
  double covered_build_s() const { return covered_build_s_; }

  // Converts a traced path to the core Path (material names filled in).
  Path to_path(const TracedPath& p) const;

 private:
  // Facets sharing one plane (exact mode): one image per plane, Embree says which facet is hit.
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
    int axis_k = 0, axis_sign = 0;  // normal = axis_sign · unit(axis_k) exactly, or axis_sign = 0
  };
  // Exact mode (no candidate rays). Facets with bitwise the same normal and offsets within 1e-7 m of their
  // neighbours form an exact group; its facets are binned in a grid over the group's extent in the two world
  // axes the plane projects onto, each facet's bounds padded by its flatness and by more than inside_box's
  // 1e-6 m, so a point that inside_box and point_on_facet accept lies in a cell holding that facet. Per link
  // and group, the image points in the lowest and highest member plane bound where any member's image point
  // can be (it moves monotonically along A⊥–T⊥ with the offset); only facets binned in those cells are
  // tested, each facet's image point computed from its own plane as reflections_exhaustive does, and the
  // survivors are taken in facet order: the same paths as the exhaustive search, and no ray for a point on
  // no facet.
  struct ExactGroup {
    Vec3 normal;
    uint32_t lo_facet = 0, hi_facet = 0;  // the members of lowest and highest offset
    double offset_lo_m = 0.0, offset_hi_m = 0.0;
    double span_m = 0.0;                  // highest − lowest offset
    int axis_u = 0, axis_v = 1;
    int axis_k = 0, axis_sign = 0;  // normal = axis_sign · unit(axis_k) exactly, or axis_sign = 0
    int nu = 1, nv = 1;
    double u0 = 0, v0 = 0, inv_du = 0, inv_dv = 0;
    uint32_t first_cell = 0;  // into cell_start_
    int bnu = 1, bnv = 1;     // occupancy bitmap over the same extent, finer
    double binv_du = 0, binv_dv = 0;
    size_t first_bit = 0;     // into exact_bits_
  };
  void build_exact_groups();
  // Marks facets whose triangles cover their bounding rectangle exactly (below: full_rect_).
  void build_full_rects();
  // `groups`: the exact groups to search (ascending ids; null: every group), from exact_groups_near.
  void reflections_exact(const Endpoint& a, const Endpoint& t, double f, const std::vector<uint32_t>* groups,
                         std::vector<TracedPath>& out) const;
  // The exact groups that can hold a reflection point of some link from `antenna` to a tag inside the box
  // [tags_lo, tags_hi], ascending: every group except those where, for every tag of the box,
  // reflections_exact's per-link tests provably reject the group (plane between the endpoints; or the
  // window of reflection points off the group's grid or on empty occupancy bits only). Shared by the links
  // of a block of nearby tags (trace_sum), it replaces the scan of every group per link.
  void exact_groups_near(const Vec3& antenna, const Vec3& tags_lo, const Vec3& tags_hi,
                         std::vector<uint32_t>& out) const;

  // The occupancy bit of point p's cell on g's grid, or SIZE_MAX off the grid. Inline: the double-bounce pair
  // loop calls it twice per pair.
  size_t cell_bit(const PlaneGroup& g, const Vec3& p) const {
    const double fu = (p[g.axis_u] - g.u0) * g.inv_du, fv = (p[g.axis_v] - g.v0) * g.inv_dv;
    if (!(fu >= 0.0 && fv >= 0.0 && fu < g.nu && fv < g.nv)) return SIZE_MAX;
    return g.bit_offset + static_cast<size_t>(fv) * g.nu + static_cast<size_t>(fu);
  }
  // Marks the occupied cells of g under the footprint of a candidate ray (direction dir, footprint radius
  // radius_m across the ray) that hit at p as seen.
  void mark_seen(const PlaneGroup& g, const Vec3& p, const Vec3& dir, double radius_m, PoseCandidates& out) const;

  // los_hint: −1 = trace the level-los visibility ray here, 0 = known clear, 1 = known blocked.
  // exact_groups: as reflections_exact's `groups`.
  // plane_pairs: as double_reflections' `pairs`; edge_pairs: as double_diffractions' `block`.
  void trace_impl(const Endpoint& antenna, const Endpoint& tag, double frequency_hz, const PoseCandidates& candidates,
                  int los_hint, const std::vector<uint32_t>* exact_groups, const std::vector<PlanePair>* plane_pairs,
                  const EdgePairBlock* edge_pairs, std::vector<TracedPath>& out) const;
  static void check_link(const Endpoint& antenna, const Endpoint& tag, double frequency_hz);
  void direct_path(const Endpoint& a, const Endpoint& t, double f, int los_hint, std::vector<TracedPath>& out) const;
  void reflections_exhaustive(const Endpoint& a, const Endpoint& t, double f, std::vector<TracedPath>& out) const;
  void reflections_by_plane(const Endpoint& a, const Endpoint& t, double f, const PoseCandidates& c,
                        const std::vector<uint32_t>* exact_groups, std::vector<TracedPath>& out) const;
  void try_plane(uint32_t group, const Endpoint& a, const Endpoint& t, double f, const PoseCandidates& c,
                 std::vector<TracedPath>& out) const;
  // Shared tail of both modes: P on facet f is valid; checks leg 2 (and leg 1 if asked) and appends.
  void add_reflection(uint32_t facet, const Vec3& image, const Vec3& p, const Endpoint& a, const Endpoint& t,
                      double f, bool check_leg1, std::vector<TracedPath>& out) const;
  bool point_on_facet(const Facet& facet, const Vec3& p) const;
  bool point_on_triangle(const Vec3& facet_normal, uint32_t mesh, uint32_t triangle, const Vec3& p) const;
  // Level double-bounce (double_bounce.cpp): every ordered plane pair, or only `pairs` when given (from
  // plane_pairs_near); `floor` is the drop floor so far (power).
  void double_reflections(const Endpoint& a, const Endpoint& t, double f, const PoseCandidates& c, double floor,
                          const std::vector<PlanePair>* pairs, std::vector<TracedPath>& out) const;
  // The ordered plane pairs (g1, g2) that can carry a double reflection of some link from `antenna` to a tag
  // inside the box [tags_lo, tags_hi]: every pair except those where, for every tag of the box, the point on
  // plane 2 or the point on plane 1 provably falls off that plane's occupancy grid or on empty cells only
  // (try_plane_pair's first rejections). Shared by the links of a block of nearby tags (trace_sum): the
  // per-link search then walks these pairs instead of all n² (the same paths: see double_bounce.cpp).
  void plane_pairs_near(const Vec3& antenna, const Vec3& tags_lo, const Vec3& tags_hi,
                        std::vector<PlanePair>& out) const;
  // The (u, v) rectangle of g's plane that holds the reflection point between `apex` and every point of the
  // box [lo, hi], widened by a rounding margin (metres, in *margin_m when given; *amplification: the bound
  // on 1 / cos of the incidence on g it assumed); false when it cannot be bounded so (g not axis-aligned, or
  // apex and box not strictly on one side of it).
  bool reflection_window(const PlaneGroup& g, const Vec3& apex, const Vec3& lo, const Vec3& hi, double region[2][2],
                         double* margin_m = nullptr, double* amplification = nullptr) const;
  // Whether any occupancy bit of g under the (u, v) rectangle is set (true when the rectangle is too large to
  // scan cheaply); false when the rectangle is off g's grid.
  bool any_occupied(const PlaneGroup& g, const double region[2][2]) const;
  // Per link and plane group, what every pair with that plane first (A's signed distance) or second (the tag's
  // signed distance and its image) would compute alike: computed once per link, by the same expressions, so a pair
  // reads the same values it would have computed (double_bounce.cpp).
  struct LinkImages {
    std::vector<double> antenna_offset_m;  // n·A − c
    std::vector<double> tag_offset_m;      // n·T − c
    std::vector<Vec3> tag_image;           // T − 2(n·T − c)n
  };
  // One ordered pair: the cheap rejections (signs, length, occupancy), then trace_plane_pair for what is left
  // (most pairs of most links end here: inline in the loops, the rest out of line).
  void try_plane_pair(uint32_t g1, uint32_t g2, const Endpoint& a, const Endpoint& t, double f,
                      const PoseCandidates& c, double floor, const LinkImages& images,
                      std::vector<TracedPath>& out) const;
  void trace_plane_pair(uint32_t g1, uint32_t g2, const Endpoint& a, const Endpoint& t, double f, double floor,
                        Vec3 t21, Vec3 p1, Vec3 p2, std::vector<TracedPath>& out) const;
  // Levels full-selective and full (post_scattering.cpp): the field scattered by each thin post.
  void post_scatterings(const Endpoint& a, const Endpoint& t, double f, double floor, std::vector<TracedPath>& out) const;
  // Whether a facet belongs to a thin post modelled as a cylinder (false for kNoFacet and below full-selective).
  bool is_post_facet(uint32_t facet) const {
    return facet != kNoFacet && !posts_.post_of_facet.empty() && posts_.post_of_facet[facet] != kNoPost;
  }
  // EmbreeScene::TriangleFilter for a post's legs (`user` is the PathFinder): its triangles are transparent.
  static bool skip_post_triangle(const void* user, uint32_t geom, uint32_t prim) {
    const PathFinder& self = *static_cast<const PathFinder*>(user);
    return self.is_post_facet(self.scene_->facet_of(self.scene_->triangle_id(geom, prim)));
  }
  // Level full (diffraction.cpp): every edge.
  void diffractions(const Endpoint& a, const Endpoint& t, double f, double floor, std::vector<TracedPath>& out) const;
  // Levels full-selective and full (double_diffraction.cpp): every pair of edge_pairs_, in both orders, or only the
  // orders of `block` when given (from edge_pairs_near: the same paths).
  void double_diffractions(const Endpoint& a, const Endpoint& t, double f, double floor, const EdgePairBlock* block,
                           std::vector<TracedPath>& out) const;
  // The orders of edge pairs that can carry a second-order path of some link from `antenna` to a tag inside the box
  // [tags_lo, tags_hi]: every order except those that double_diffractions' per-link tests provably reject for every
  // tag of the box (a parallel pair whose points fall off an edge; a corner pair whose shortest path is through its
  // corner), with the edges and corners they read. Shared by the links of a block of nearby tags (trace_sum).
  void edge_pairs_near(const Vec3& antenna, const Vec3& tags_lo, const Vec3& tags_hi, EdgePairBlock& out) const;

  std::shared_ptr<const Scene> scene_;
  TraceOptions options_;
  double drop_power_ratio_ = 0.0;  // db_to_linear(-drop_below_db)
  double max_length2_ = 0.0;       // max_path_length_m²
  std::vector<PlaneGroup> planes_;
  // The axis-aligned planes per axis k, sorted by their coordinate x_k (axis_sign · offset_m), and the others:
  // double-bounce skips, per link and second plane, the first planes whose coordinate lies between A's and T's
  // image's (double_bounce.cpp).
  struct AxisPlane {
    double coordinate_m = 0.0;
    uint32_t plane = 0;
  };
  std::array<std::vector<AxisPlane>, 3> planes_by_axis_;
  std::vector<uint32_t> planes_off_axis_;
  std::vector<uint32_t> axis_position_;  // an axis-aligned plane's index in its planes_by_axis_ list
  double max_plane_coordinate_m_ = 0.0;  // the largest |coordinate_m| of planes_by_axis_
  std::vector<uint32_t> plane_of_facet_;
  std::vector<std::vector<uint32_t>> plane_members_;  // facets of each plane group
  std::vector<Edge> edges_;
  std::vector<EdgePair> edge_pairs_;  // edge pairs within TraceOptions::double_diffraction_max_m (edge_pairs.h)
  // What the second-order loop reads per link instead of per pair (double_diffraction.cpp, index_edge_pairs): every
  // edge of edge_pairs_ once, ascending; the corners where a non-parallel pair's edges meet, and for each pair and
  // order of the tracer (2·pair + order) its corner's index, −1 if the edges do not meet at an end.
  std::vector<uint32_t> paired_edges_;
  std::vector<Vec3> pair_corners_;
  std::vector<int32_t> pair_corner_of_;
  double max_edge_coordinate_m_ = 0.0;  // the largest |coordinate| of a paired edge's ends (edge_pairs_near's margin)
  void index_edge_pairs();
  ThinPosts posts_;
  std::vector<uint64_t> occupancy_;
  std::vector<ExactGroup> exact_groups_;
  std::vector<uint32_t> cell_start_;   // CSR over every exact group's cells into cell_facets_
  struct CellEntry {                   // a facet whose padded bounds overlap the cell, with those (u, v) bounds
    float u_lo, u_hi, v_lo, v_hi;
    uint32_t facet;
  };
  std::vector<CellEntry> cell_facets_;  // facets ascending within each cell
  struct PlaneBox {                    // a facet's plane and bounds, packed for the exact search's scan
    Vec3 normal;
    double offset_m;
    Vec3 lo, hi;
  };
  std::vector<PlaneBox> plane_box_;    // per facet
  std::vector<uint64_t> exact_bits_;   // occupancy bitmaps of the exact groups
  // Per facet, 1 if it lies exactly in an axis-aligned plane (normal ±unit, every vertex's coordinate on that
  // axis bitwise equal) and its triangles cover its bounding rectangle: the edges occurring an odd number of
  // times among them (welded by exact position) all lie on the rectangle's sides and its centre is in an odd
  // number of them (the mod-2 argument of raytrace/covered_rects.h). A point of that closed rectangle is
  // then on some closed triangle of the facet, so point_on_facet — whose tolerance only adds — is true
  // there: reflections_exact skips it (a cheap early exit, the same decision).
  std::vector<uint8_t> full_rect_;
  std::unique_ptr<CoveredRects> covered_;
  double covered_build_s_ = 0.0;
  std::vector<Vec3> candidate_directions_;
  double candidate_spacing_rad_ = 0.0;  // angular spacing of the candidate rays, √(4π/N)
};

}  // namespace rfidray
