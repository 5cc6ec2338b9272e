#include "raytrace/path_finder.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <map>
#include <tuple>

#include <omp.h>

#include "core/error.h"
#include "core/fresnel.h"
#include "core/units.h"
#include "raytrace/bit_grid.h"
#include "raytrace/image_geometry.h"

namespace rfidray {
namespace {

// The bounding box of the tags tags[block[…]] (block not empty): what a block of nearby tags shares.
void tag_block_box(std::span<const Endpoint> tags, std::span<const uint32_t> block, Vec3& lo, Vec3& hi) {
  lo = hi = tags[block[0]].pose.position;
  for (size_t j = 1; j < block.size(); ++j)
    lo = lo.cwiseMin(tags[block[j]].pose.position), hi = hi.cwiseMax(tags[block[j]].pose.position);
}

bool inside_box(const Vec3& p, const Vec3& lo, const Vec3& hi, double tol) {
  return (p.array() >= lo.array() - tol).all() && (p.array() <= hi.array() + tol).all();
}

// Cheap key so coplanar facets (within ~1e-6) share a plane group.
std::tuple<int64_t, int64_t, int64_t, int64_t> plane_key(Vec3 n, double c) {
  // Canonical sign: the largest component positive.
  int k = 0;
  n.cwiseAbs().maxCoeff(&k);
  if (n[k] < 0.0) {
    n = -n;
    c = -c;
  }
  return {std::llround(n.x() * 1e6), std::llround(n.y() * 1e6), std::llround(n.z() * 1e6), std::llround(c * 1e6)};
}

}  // namespace

PathFinder::PathFinder(std::shared_ptr<const Scene> scene, const TraceOptions& options)
    : scene_(std::move(scene)), options_(options) {
  if (!scene_) throw InputError("ray-traced channel: no scene");
  if (!(options_.drop_below_db >= 0.0)) throw field_error("drop_below_db", "must be ≥ 0 dB");
  if (!(options_.max_path_length_m > 0.0)) throw field_error("max_path_length_m", "must be > 0 m");
  if (!(options_.endpoint_epsilon_m > 0.0) || !(options_.surface_epsilon_m > 0.0))
    throw field_error("epsilon", "ray epsilons must be > 0");
  if (options_.candidate_rays < 0) throw field_error("candidate_rays", "must be ≥ 0");
  if (!(options_.candidate_spread > 0.0)) throw field_error("candidate_spread", "must be > 0");
  drop_power_ratio_ = db_to_linear(-options_.drop_below_db);
  max_length2_ = options_.max_path_length_m * options_.max_path_length_m;
  // Plane groups of the exact mode.
  const auto& facets = scene_->facets();
  std::map<std::tuple<int64_t, int64_t, int64_t, int64_t>, uint32_t> group_of_key;
  plane_of_facet_.resize(facets.size());
  for (size_t f = 0; f < facets.size(); ++f) {
    const Facet& fc = facets[f];
    auto [it, inserted] = group_of_key.emplace(plane_key(fc.normal, fc.offset_m), static_cast<uint32_t>(planes_.size()));
    if (inserted) planes_.push_back({fc.normal, fc.offset_m, fc.lo, fc.hi});
    PlaneGroup& g = planes_[it->second];
    g.lo = g.lo.cwiseMin(fc.lo);
    g.hi = g.hi.cwiseMax(fc.hi);
    g.flatness_m = std::max(g.flatness_m, fc.flatness_m);
    plane_of_facet_[f] = it->second;
  }
  // Occupancy bitmaps: ~64 cells per facet (at most 2^18 per plane), shaped like the plane's extent.
  plane_members_.assign(planes_.size(), {});
  std::vector<std::vector<uint32_t>>& members = plane_members_;
  for (size_t f = 0; f < facets.size(); ++f) members[plane_of_facet_[f]].push_back(static_cast<uint32_t>(f));
  constexpr double kPad = 1e-6;  // metres: facet bounds are padded so rounding never loses a cell
  for (size_t gi = 0; gi < planes_.size(); ++gi) {
    PlaneGroup& g = planes_[gi];
    int k = 0;
    g.normal.cwiseAbs().maxCoeff(&k);
    g.axis_u = (k + 1) % 3;
    g.axis_v = (k + 2) % 3;
    if (g.normal == Vec3::Unit(k) || g.normal == -Vec3::Unit(k)) g.axis_k = k, g.axis_sign = g.normal[k] > 0 ? 1 : -1;
    const double eu = std::max(g.hi[g.axis_u] - g.lo[g.axis_u], 1e-6);
    const double ev = std::max(g.hi[g.axis_v] - g.lo[g.axis_v], 1e-6);
    const double target = std::clamp(64.0 * members[gi].size(), 1.0, 262144.0);
    g.nu = static_cast<int>(std::clamp(std::round(std::sqrt(target * eu / ev)), 1.0, 4096.0));
    g.nv = static_cast<int>(std::clamp(std::ceil(target / g.nu), 1.0, 4096.0));
    g.u0 = g.lo[g.axis_u] - kPad;
    g.v0 = g.lo[g.axis_v] - kPad;
    g.inv_du = g.nu / (eu + 2 * kPad);
    g.inv_dv = g.nv / (ev + 2 * kPad);
    g.bit_offset = occupancy_.size() * 64;
    occupancy_.resize(occupancy_.size() + (static_cast<size_t>(g.nu) * g.nv + 63) / 64, 0);
    auto cell = [](double x, double x0, double inv, int n) {
      return std::clamp(static_cast<int>(std::floor((x - x0) * inv)), 0, n - 1);
    };
    for (uint32_t f : members[gi]) {
      const Facet& fc = facets[f];
      const int iu0 = cell(fc.lo[g.axis_u] - kPad, g.u0, g.inv_du, g.nu), iu1 = cell(fc.hi[g.axis_u] + kPad, g.u0, g.inv_du, g.nu);
      const int iv0 = cell(fc.lo[g.axis_v] - kPad, g.v0, g.inv_dv, g.nv), iv1 = cell(fc.hi[g.axis_v] + kPad, g.v0, g.inv_dv, g.nv);
      for (int iv = iv0; iv <= iv1; ++iv)
        for (int iu = iu0; iu <= iu1; ++iu) {
          const size_t bit = g.bit_offset + static_cast<size_t>(iv) * g.nu + iu;
          occupancy_[bit / 64] |= uint64_t{1} << (bit % 64);
        }
    }
  }
  for (auto& list : planes_by_axis_) list.clear();
  planes_off_axis_.clear();
  for (uint32_t gi = 0; gi < planes_.size(); ++gi) {
    const PlaneGroup& g = planes_[gi];
    if (g.axis_sign == 0) planes_off_axis_.push_back(gi);
    else planes_by_axis_[g.axis_k].push_back({g.axis_sign * g.offset_m, gi});
  }
  max_plane_coordinate_m_ = 0.0;
  for (const auto& list : planes_by_axis_)
    for (const AxisPlane& p : list) max_plane_coordinate_m_ = std::max(max_plane_coordinate_m_, std::abs(p.coordinate_m));
  for (auto& list : planes_by_axis_)
    std::sort(list.begin(), list.end(), [](const AxisPlane& x, const AxisPlane& y) {
      return x.coordinate_m != y.coordinate_m ? x.coordinate_m < y.coordinate_m : x.plane < y.plane;
    });
  axis_position_.assign(planes_.size(), 0);
  for (const auto& list : planes_by_axis_)
    for (uint32_t i = 0; i < list.size(); ++i) axis_position_[list[i].plane] = i;
  build_exact_groups();
  if (options_.candidates == CandidateMode::kExact && includes(options_.level, ChannelLevel::kSingleBounce))
    build_full_rects();
  if (options_.cull_covered && options_.candidates == CandidateMode::kExact &&
      includes(options_.level, ChannelLevel::kSingleBounce) && !scene_->empty()) {
    const auto t0 = std::chrono::steady_clock::now();
    covered_ = std::make_unique<CoveredRects>(scene_->meshes(), scene_->local_origin());
    covered_build_s_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  // Spherical Fibonacci directions for the optional per-pose candidate search.
  const int n = options_.candidate_rays;
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < n; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / n;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    candidate_directions_.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  if (n > 0) candidate_spacing_rad_ = std::sqrt(4.0 * kPi / n);
  if (includes(options_.level, ChannelLevel::kFullSelective)) {
    edges_ = extract_edges(*scene_);
    posts_ = find_thin_posts(*scene_, edges_, options_.thin_post_max_width_m);
    std::vector<uint8_t> post_edge(edges_.size(), 0);
    for (size_t i = 0; i < edges_.size(); ++i) post_edge[i] = posts_.post_of_edge[i] != kNoPost;
    edge_pairs_ = find_edge_pairs(edges_, post_edge, options_.double_diffraction_max_m);
    index_edge_pairs();
  }
}

void PathFinder::mark_seen(const PlaneGroup& g, const Vec3& p, const Vec3& dir, double radius_m,
                           PoseCandidates& out) const {
  // The footprint is an ellipse: radius across the ray, radius / cos θ along the ray's projection on the
  // plane (θ capped at 80° so grazing hits do not flood a plane). Its bounding box in the plane's (u, v):
  const double cos_inc = std::max(std::abs(dir.dot(g.normal)), 0.17);
  const double pu = dir[g.axis_u], pv = dir[g.axis_v], pn = std::sqrt(pu * pu + pv * pv);
  const double cu = pn > 1e-12 ? pu / pn : 1.0, cv = pn > 1e-12 ? pv / pn : 0.0;  // projected direction
  const double stretch = 1.0 / cos_inc;
  // (sqrt, not std::hypot: hypot's overflow care costs more than the rest of the marking here)
  const double half_u = radius_m * std::sqrt(cu * cu * stretch * stretch + cv * cv);
  const double half_v = radius_m * std::sqrt(cv * cv * stretch * stretch + cu * cu);
  const auto range = [](double x, double r, double x0, double inv, int n) {
    return std::pair{std::clamp(static_cast<int>(std::floor((x - r - x0) * inv)), 0, n - 1),
                     std::clamp(static_cast<int>(std::floor((x + r - x0) * inv)), 0, n - 1)};
  };
  const auto [iu0, iu1] = range(p[g.axis_u], half_u, g.u0, g.inv_du, g.nu);
  const auto [iv0, iv1] = range(p[g.axis_v], half_v, g.v0, g.inv_dv, g.nv);
  for (int iv = iv0; iv <= iv1; ++iv)
    for (int iu = iu0; iu <= iu1; ++iu) {
      const size_t bit = g.bit_offset + static_cast<size_t>(iv) * g.nu + iu;
      // Only occupied cells are marked, so one lookup in try_plane answers "a facet is there and was seen".
      const uint64_t mask = (uint64_t{1} << (bit % 64)) & occupancy_[bit / 64];
      if (!mask) continue;
      uint64_t& word = out.seen_cells[bit / 64];
      if (word == 0) out.touched_words.push_back(static_cast<uint32_t>(bit / 64));
      word |= mask;
    }
}

void PathFinder::prepare_pose(const Vec3& antenna_position, PoseCandidates& out) const {
  out.planes.clear();
  out.all = options_.candidates != CandidateMode::kExact || candidate_directions_.empty();
  if (out.all || !includes(options_.level, ChannelLevel::kSingleBounce)) return;  // nothing to search for
  if (out.seen_cells.size() != occupancy_.size()) {
    out.seen_cells.assign(occupancy_.size(), 0);
    out.touched_words.clear();
  }
  for (uint32_t w : out.touched_words) out.seen_cells[w] = 0;
  out.touched_words.clear();
  // The rays are the expensive part: in parallel unless the caller already is (simulate runs antennas in
  // parallel); the marking after them is serial and in ray order, so the result never depends on threads.
  const EmbreeScene& bvh = scene_->bvh();
  const auto n = static_cast<std::ptrdiff_t>(candidate_directions_.size());
  out.hits.resize(candidate_directions_.size());
#pragma omp parallel for schedule(static) if (n >= 2048 && !omp_in_parallel())
  for (std::ptrdiff_t i = 0; i < n; ++i)
    out.hits[i] = bvh.intersect(antenna_position, candidate_directions_[i], options_.endpoint_epsilon_m, 1e30);
  std::vector<char>& plane_seen = out.plane_seen;
  plane_seen.assign(planes_.size(), 0);
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    const RayHit& h = out.hits[i];
    if (!h.hit) continue;
    const uint32_t tri = scene_->triangle_id(h.geom, h.prim);
    const uint32_t f = scene_->facet_of(tri);
    if (f == kNoFacet) continue;
    const uint32_t gi = plane_of_facet_[f];
    const PlaneGroup& g = planes_[gi];
    plane_seen[gi] = 1;
    // The ray's footprint radius: the distance to the neighbouring rays (so footprints overlap) times the
    // spread factor.
    const double radius = options_.candidate_spread * h.t * candidate_spacing_rad_;
    mark_seen(g, antenna_position + h.t * candidate_directions_[i], candidate_directions_[i], radius, out);
  }
  for (size_t gi = 0; gi < plane_seen.size(); ++gi)
    if (plane_seen[gi]) out.planes.push_back(static_cast<uint32_t>(gi));
}

void PathFinder::decide_plane_pair_sharing(const Vec3& a, std::span<const Endpoint> tags,
                                           std::span<const uint32_t> order, PoseCandidates& out) const {
  out.share_plane_pairs = false;
  if (!includes(options_.level, ChannelLevel::kDoubleBounce) || planes_.size() < 2) return;
  if (options_.plane_pair_sharing != TraceOptions::Sharing::kAuto) {
    out.share_plane_pairs = options_.plane_pair_sharing == TraceOptions::Sharing::kAlways;
    return;
  }
  // The probe costs one block's pairs: worth it only when many blocks follow. Sharing pays while fewer than
  // 0.42 of the pairs are kept: a block's pairs cost ~72 ns per pair against ~7.8 ns per pair and link without
  // sharing since the pair loop was made cheaper (bench_levels on the paper warehouse, 2026-12-07: 75.4 µs per
  // link unshared, 77.9 shared with 46 % of the pairs kept), i.e. 9.2 links' worth, saved 16 times per pair
  // pruned: 16·(1 − kept) > 9.2. (It was 2/3 when a pair cost ~12 ns per link, five links' worth.)
  constexpr size_t kBlock = 16, kMinTags = 64;
  if (order.size() < kMinTags) return;
  Vec3 lo, hi;
  tag_block_box(tags, order.first(kBlock), lo, hi);
  if (!lo.allFinite() || !hi.allFinite() || !a.allFinite()) return;
  thread_local std::vector<PlanePair> tl_probe;
  plane_pairs_near(a, lo, hi, tl_probe);
  const double all_pairs = static_cast<double>(planes_.size()) * static_cast<double>(planes_.size() - 1);
  constexpr double kMaxKeptShare = 0.42;
  out.share_plane_pairs = static_cast<double>(tl_probe.size()) < kMaxKeptShare * all_pairs;
}

void PathFinder::decide_edge_pair_sharing(const Vec3& a, std::span<const Endpoint> tags,
                                          std::span<const uint32_t> order, PoseCandidates& out) const {
  out.share_edge_pairs = false;
  if (!includes(options_.level, ChannelLevel::kFullSelective) || edge_pairs_.empty()) return;
  if (options_.edge_pair_sharing != TraceOptions::Sharing::kAuto) {
    out.share_edge_pairs = options_.edge_pair_sharing == TraceOptions::Sharing::kAlways;
    return;
  }
  // As for plane pairs, by measurement: w1m coverage maps at `full` (bench/results/levels/README.md, "Edge pairs
  // shared per block") took 0.66× the time shared where a block keeps 2 % of the orders (tags 25 cm apart),
  // 0.90× at 11–21 % (1 m apart) and 0.96–1.01× at 23–26 % (2.5 m apart): share below 0.3.
  constexpr size_t kBlock = 16, kMinTags = 64;
  constexpr double kMaxKeptShare = 0.3;
  if (order.size() < kMinTags) return;
  Vec3 lo, hi;
  tag_block_box(tags, order.first(kBlock), lo, hi);
  if (!lo.allFinite() || !hi.allFinite() || !a.allFinite()) return;
  thread_local EdgePairBlock tl_probe;
  edge_pairs_near(a, lo, hi, tl_probe);
  const double all_orders = 2.0 * static_cast<double>(edge_pairs_.size());
  out.share_edge_pairs = static_cast<double>(tl_probe.orders.size()) < kMaxKeptShare * all_orders;
}

void PathFinder::check_link(const Endpoint& antenna, const Endpoint& tag, double frequency_hz) {
  const Vec3& a = antenna.pose.position;
  const Vec3& t = tag.pose.position;
  const double d = (t - a).norm();
  if (!all_finite(a) || !all_finite(t) || !(d > 0.0))
    throw InputError("link: antenna and tag coincide or are not finite (distance " + std::to_string(d) + " m)");
  if (!(frequency_hz > 0.0) || !std::isfinite(frequency_hz))
    throw InputError("link: frequency must be > 0 Hz (got " + std::to_string(frequency_hz) + ")");
}

void PathFinder::trace(const Endpoint& antenna, const Endpoint& tag, double frequency_hz,
                       const PoseCandidates& candidates, std::vector<TracedPath>& out) const {
  trace_impl(antenna, tag, frequency_hz, candidates, -1, nullptr, nullptr, nullptr, out);
}

void PathFinder::trace_sum(const Endpoint& antenna, std::span<const Endpoint> tags, std::span<const uint32_t> which,
                           double frequency_hz, const PoseCandidates& candidates, int packet_width,
                           std::span<std::complex<double>> h) const {
  thread_local std::vector<TracedPath> tl_paths;  // per-thread scratch: no allocation once warm
  std::vector<TracedPath>& paths = tl_paths;
  const auto sum = [&](uint32_t k, int hint, const std::vector<uint32_t>* groups = nullptr,
                       const std::vector<PlanePair>* pairs = nullptr, const EdgePairBlock* edge_pairs = nullptr) {
    trace_impl(antenna, tags[k], frequency_hz, candidates, hint, groups, pairs, edge_pairs, paths);
    std::complex<double> s{0.0, 0.0};
    for (const TracedPath& p : paths) s += p.contribution;
    h[k] = s;
  };
  if (options_.level != ChannelLevel::kLos || packet_width <= 1 || scene_->empty()) {
    const bool group_blocks = includes(options_.level, ChannelLevel::kSingleBounce) &&
                              options_.candidates != CandidateMode::kExhaustive && candidates.all &&
                              !exact_groups_.empty();
    const bool pair_blocks = candidates.share_plane_pairs && includes(options_.level, ChannelLevel::kDoubleBounce) &&
                             planes_.size() >= 2;
    const bool edge_blocks = candidates.share_edge_pairs && includes(options_.level, ChannelLevel::kFullSelective) &&
                             !edge_pairs_.empty();
    if (!group_blocks && !pair_blocks && !edge_blocks) {
      for (uint32_t k : which) sum(k, -1);
      return;
    }
    // Per block of 16 nearby tags (the callers pass them in Morton order): the exact search's groups, the
    // double-bounce search's plane pairs and second-order diffraction's edge pairs that can matter for any tag of
    // the block, found once, instead of every group and every pair for every link.
    thread_local std::vector<uint32_t> tl_groups;
    thread_local std::vector<PlanePair> tl_pairs;
    thread_local EdgePairBlock tl_edge_block;
    std::vector<uint32_t>& groups = tl_groups;
    std::vector<PlanePair>& pairs = tl_pairs;
    EdgePairBlock& edge_block = tl_edge_block;
    constexpr size_t kTagBlock = 16;
    for (size_t i = 0; i < which.size(); i += kTagBlock) {
      const size_t n = std::min(kTagBlock, which.size() - i);
      Vec3 lo, hi;
      tag_block_box(tags, which.subspan(i, n), lo, hi);
      // (A non-finite endpoint: every group and pair; the link's own check then throws.)
      const bool finite = lo.allFinite() && hi.allFinite() && antenna.pose.position.allFinite();
      if (finite && group_blocks) exact_groups_near(antenna.pose.position, lo, hi, groups);
      const bool share_pairs = finite && pair_blocks;
      if (share_pairs) plane_pairs_near(antenna.pose.position, lo, hi, pairs);
      const bool share_edges = finite && edge_blocks;
      if (share_edges) edge_pairs_near(antenna.pose.position, lo, hi, edge_block);
      for (size_t j = 0; j < n; ++j)
        sum(which[i + j], -1, finite && group_blocks ? &groups : nullptr, share_pairs ? &pairs : nullptr,
            share_edges ? &edge_block : nullptr);
    }
    return;
  }
  // Level los in packets: the visibility of up to 16 links per Embree call, then each link's path with its
  // known visibility. Links too long for a path get an inactive lane (and no path). A segment parallel to a
  // coordinate plane (a direction component below 1e-6) is traced alone with rtcOccluded1, as trace() does:
  // it is the one kind of ray that can lie in a surface's plane in a scene of axis-aligned surfaces (antenna
  // and tag at a shelf's height), where Embree's packet and single-ray kernels may disagree
  // (raytrace/embree_scene.h); any other ray crosses such planes and both kernels agree on it.
  constexpr size_t kBlock = 16;
  constexpr double kAxisParallel = 1e-6;
  std::array<Segment, kBlock> seg;
  std::array<bool, kBlock> blocked{}, alone{};
  for (size_t i = 0; i < which.size(); i += kBlock) {
    const size_t n = std::min(kBlock, which.size() - i);
    for (size_t j = 0; j < n; ++j) {
      const Endpoint& t = tags[which[i + j]];
      check_link(antenna, t, frequency_hz);  // trace()'s checks, before any ray
      alone[j] = false;
      if (!direct_segment(antenna.pose.position, t.pose.position, seg[j])) {
        seg[j].tnear = seg[j].tfar = 0.0;
      } else if (seg[j].dir.cwiseAbs().minCoeff() < kAxisParallel) {
        alone[j] = true;
        seg[j].tnear = seg[j].tfar = 0.0;
      }
    }
    scene_->bvh().occluded_many(packet_width, seg.data(), n, blocked.data());
    for (size_t j = 0; j < n; ++j) {
      if (alone[j])
        sum(which[i + j], -1);
      else if (blocked[j])
        h[which[i + j]] = {0.0, 0.0};  // trace() finds no path for a blocked link at level los
      else
        sum(which[i + j], 0);
    }
  }
}

bool PathFinder::direct_segment(const Vec3& a, const Vec3& t, Segment& s, double* length_m) const {
  const Vec3 delta = t - a;
  const double length = delta.norm();
  if (length_m) *length_m = length;
  if (length > options_.max_path_length_m) return false;
  const double eps = std::min(options_.endpoint_epsilon_m, 0.25 * length);
  s.origin = a;
  s.dir = delta / length;
  s.tnear = eps;
  s.tfar = length - eps;
  return true;
}

void PathFinder::trace_impl(const Endpoint& antenna, const Endpoint& tag, double frequency_hz,
                            const PoseCandidates& candidates, int los_hint,
                            const std::vector<uint32_t>* exact_groups, const std::vector<PlanePair>* plane_pairs,
                            const EdgePairBlock* edge_pairs, std::vector<TracedPath>& out) const {
  out.clear();
  if (los_hint < 0) check_link(antenna, tag, frequency_hz);  // (trace_sum checked before its packet)
  direct_path(antenna, tag, frequency_hz, los_hint, out);
  if (includes(options_.level, ChannelLevel::kSingleBounce)) {
    const size_t first = out.size();
    if (options_.candidates == CandidateMode::kExhaustive)
      reflections_exhaustive(antenna, tag, frequency_hz, out);
    else
      reflections_by_plane(antenna, tag, frequency_hz, candidates, exact_groups, out);
    std::sort(out.begin() + first, out.end(), [](const TracedPath& x, const TracedPath& y) {
      return std::tie(x.length_m, x.facet) < std::tie(y.length_m, y.facet);
    });
  }
  // The drop floor so far: the strongest path can only grow, so what is below it now is dropped at the end.
  auto floor_so_far = [&] {
    double strongest = 0.0;
    for (const TracedPath& p : out) strongest = std::max(strongest, std::norm(p.contribution));
    return strongest * drop_power_ratio_;
  };
  if (includes(options_.level, ChannelLevel::kDoubleBounce)) {
    const size_t first = out.size();
    double_reflections(antenna, tag, frequency_hz, candidates, floor_so_far(), plane_pairs, out);
    std::sort(out.begin() + first, out.end(), [](const TracedPath& x, const TracedPath& y) {
      return std::tie(x.length_m, x.facet, x.facet2) < std::tie(y.length_m, y.facet, y.facet2);
    });
  }
  if (includes(options_.level, ChannelLevel::kFullSelective)) {
    // Thin posts before the edges: their fields are part of the h that full-selective's bound is relative to.
    size_t first = out.size();
    post_scatterings(antenna, tag, frequency_hz, floor_so_far(), out);
    std::sort(out.begin() + first, out.end(), [](const TracedPath& x, const TracedPath& y) {
      return std::tie(x.length_m, x.post) < std::tie(y.length_m, y.post);
    });
    first = out.size();
    diffractions(antenna, tag, frequency_hz, floor_so_far(), out);
    std::sort(out.begin() + first, out.end(), [](const TracedPath& x, const TracedPath& y) {
      return std::tie(x.length_m, x.edge) < std::tie(y.length_m, y.edge);
    });
    first = out.size();
    double_diffractions(antenna, tag, frequency_hz, floor_so_far(), edge_pairs, out);
    std::stable_sort(out.begin() + first, out.end(), [](const TracedPath& x, const TracedPath& y) {
      return std::tie(x.length_m, x.edge, x.edge2) < std::tie(y.length_m, y.edge, y.edge2);
    });
  }
  // Drop paths far below the strongest (power ratio); a lone path is the strongest.
  if (out.size() < 2) return;
  double strongest = 0.0;
  for (const TracedPath& p : out) strongest = std::max(strongest, std::norm(p.contribution));
  const double floor = strongest * drop_power_ratio_;
  std::erase_if(out, [&](const TracedPath& p) { return std::norm(p.contribution) < floor; });
}

void PathFinder::direct_path(const Endpoint& ant, const Endpoint& tag, double f, int los_hint,
                             std::vector<TracedPath>& out) const {
  const Vec3& a = ant.pose.position;
  Segment s;
  double length = 0.0;
  if (!direct_segment(a, tag.pose.position, s, &length)) return;
  const Vec3& dir = s.dir;
  const double eps = s.tnear;
  const EmbreeScene& bvh = scene_->bvh();
  // At level `los` visibility is all that matters: one occlusion ray (or the caller's packet's answer for it),
  // and nothing more for an occluded link. Above it the first hit is needed anyway, so the segment is walked
  // with closest-hit rays from the start.
  RayHit hit;
  if (!scene_->empty()) {
    if (options_.level == ChannelLevel::kLos) {
      if (los_hint >= 0 ? los_hint == 1 : bvh.occluded(a, dir, s.tnear, s.tfar)) return;
    } else {
      hit = bvh.intersect(a, dir, eps, length - eps);
    }
  }
  const double gain = std::sqrt(ant.pattern.gain_linear_world(ant.pose.orientation, dir) *
                                tag.pattern.gain_linear_world(tag.pose.orientation, -dir));
  CVec3 field = ant.polarization.field(ant.pose.orientation, dir);
  TracedPath p;
  p.length_m = length;
  p.point = a;
  // Walk the segment surface by surface. A solid (RadioMaterial::solid) is entered at one crossing and left at
  // the next crossing of the same material: the pair is one P.2040 slab of the thickness the chord cuts along
  // the entry face's normal, d = chord · cos θ (exact for parallel faces: a wall as a box).
  constexpr uint32_t kOutside = ~0u;
  uint32_t inside_solid = kOutside;  // material index of the solid the segment is in
  double entry_t = 0.0, entry_cos = 1.0;
  Vec3 entry_normal = Vec3::Zero();
  // Where the segment meets the triangle's plane, in double (Embree's float t is ~1e-7 m off, and a 20 cm
  // concrete slab's phase turns 42 rad per metre of thickness).
  auto plane_t = [&](uint32_t tri, const Vec3& n, double t_float) {
    const double dn = dir.dot(n);
    return std::abs(dn) > 1e-12 ? n.dot(scene_->corners(tri)[0] - a) / dn : t_float;
  };
  // Leaving by a face more than 45° from parallel to the entry face (a ray cutting a wall's corner, in by the
  // front, out by the end face) is no slab: the refracted ray would leave elsewhere, and near a corner the field
  // is the edges' diffraction (FDTD beside a 20 cm concrete wall's end: 0.22 of the free-space field where this
  // straight chord as a slab gave 0.51, docs/fullwave.md). Such a path is dropped.
  constexpr double kCos45 = 0.70710678118654752;
  bool corner_cut = false;
  auto leave_solid = [&](double exit_t, const Vec3* exit_normal) {
    if (exit_normal && std::abs(exit_normal->dot(entry_normal)) < kCos45) corner_cut = true;
    const RadioMaterial& m = scene_->materials()[inside_solid];
    const double thickness_m = std::max(0.0, (exit_t - entry_t) * entry_cos);
    field = transmit_field(field, dir, entry_normal,
                           slab_transmission(m.complex_permittivity(f), entry_cos, thickness_m, f));
    inside_solid = kOutside;
  };
  while (hit.hit) {
    const uint32_t tri = scene_->triangle_id(hit.geom, hit.prim);
    // A thin post is not an obstacle at the levels that model it: its scattered field (a path of its own,
    // raytrace/post_scattering.cpp) holds its shadow.
    if (is_post_facet(scene_->facet_of(tri))) {
      hit = bvh.intersect(a, dir, hit.t + options_.surface_epsilon_m, length - eps);
      continue;
    }
    p.kind = PathKind::kBlocked;
    const uint32_t material = scene_->material_of(tri);
    const RadioMaterial& m = scene_->materials()[material];
    const Vec3 n = scene_->normal_of(tri);
    if (m.solid && inside_solid == material) {
      leave_solid(plane_t(tri, n, hit.t), &n);
      if (corner_cut) return;
    } else {
      // Another solid's face while inside one (solids of two materials touching): the first ends there. A sheet
      // inside a solid is crossed as a sheet and leaves the solid open.
      if (m.solid && inside_solid != kOutside) leave_solid(plane_t(tri, n, hit.t), nullptr);
      if (m.perfect_conductor || ++p.crossings > options_.max_crossings) return;  // opaque
      const double cos_theta = std::abs(dir.dot(n));
      if (m.solid) {
        inside_solid = material;
        entry_t = plane_t(tri, n, hit.t);
        entry_cos = cos_theta;
        entry_normal = n;
      } else {
        field = transmit_field(field, dir, n, material_transmission(m, f, cos_theta));
      }
      if (p.crossings == 1) {
        p.point = a + hit.t * dir;
        p.material = material;
      }
    }
    hit = bvh.intersect(a, dir, hit.t + options_.surface_epsilon_m, length - eps);
  }
  if (inside_solid != kOutside) leave_solid(length, nullptr);  // the tag is inside the solid
  p.coefficient = gain * polarization_match(field, tag.polarization, tag.pose.orientation, dir);
  p.contribution = path_contribution(length, p.coefficient, f);
  out.push_back(p);
}

bool PathFinder::point_on_triangle(const Vec3& facet_normal, uint32_t mesh, uint32_t tri, const Vec3& p) const {
  constexpr double kTol = 1e-9;  // metres; points on shared edges belong to both triangles
  const auto c = scene_->corners(mesh, tri);
  bool pos = true, neg = true;
  for (int k = 0; k < 3; ++k) {
    const Vec3 e = c[(k + 1) % 3] - c[k];
    const double s = facet_normal.dot(e.cross(p - c[k]));
    const double tol = kTol * e.norm();
    pos = pos && s >= -tol;
    neg = neg && s <= tol;
  }
  return pos || neg;
}

bool PathFinder::point_on_facet(const Facet& facet, const Vec3& p) const {
  for (uint32_t tri : facet.triangles)
    if (point_on_triangle(facet.normal, facet.mesh, tri, p)) return true;
  return false;
}

void PathFinder::reflections_exhaustive(const Endpoint& ant, const Endpoint& tag, double f,
                                        std::vector<TracedPath>& out) const {
  const auto& facets = scene_->facets();
  Vec3 image, p;
  for (size_t i = 0; i < facets.size(); ++i) {
    const Facet& fc = facets[i];
    if (!image_point(fc.normal, fc.offset_m, ant.pose.position, tag.pose.position, options_.surface_epsilon_m, image, p))
      continue;
    if ((image - ant.pose.position).squaredNorm() > max_length2_) continue;
    if (!inside_box(p, fc.lo, fc.hi, 1e-6) || !point_on_facet(fc, p)) continue;
    add_reflection(static_cast<uint32_t>(i), image, p, ant, tag, f, /*check_leg1=*/true, out);
  }
}

void PathFinder::build_exact_groups() {
  const auto& facets = scene_->facets();
  // Members by exact normal, then offset.
  std::vector<uint32_t> order(facets.size());
  for (uint32_t f = 0; f < order.size(); ++f) order[f] = f;
  const auto key = [&](uint32_t f) {
    const Facet& fc = facets[f];
    return std::tuple(fc.normal.x(), fc.normal.y(), fc.normal.z(), fc.offset_m, f);
  };
  std::sort(order.begin(), order.end(), [&](uint32_t x, uint32_t y) { return key(x) < key(y); });
  constexpr double kGroupGapM = 1e-7;  // offsets closer than this share a group
  constexpr double kGridPad = 4e-6;    // metres, > inside_box's 1e-6 m and point_on_triangle's tolerance
  cell_start_.assign(1, 0);
  std::vector<uint32_t> members;
  for (size_t i = 0; i < order.size();) {
    const Facet& first = facets[order[i]];
    members.assign(1, order[i]);
    size_t j = i + 1;
    for (; j < order.size(); ++j) {
      const Facet& fc = facets[order[j]];
      if (fc.normal != first.normal || fc.offset_m - facets[order[j - 1]].offset_m > kGroupGapM) break;
      members.push_back(order[j]);
    }
    i = j;
    ExactGroup g;
    g.normal = first.normal;
    g.lo_facet = members.front();
    g.hi_facet = members.back();
    g.offset_lo_m = facets[g.lo_facet].offset_m;
    g.offset_hi_m = facets[g.hi_facet].offset_m;
    g.span_m = g.offset_hi_m - g.offset_lo_m;
    int k = 0;
    g.normal.cwiseAbs().maxCoeff(&k);
    g.axis_u = (k + 1) % 3;
    g.axis_v = (k + 2) % 3;
    if (g.normal == Vec3::Unit(k) || g.normal == -Vec3::Unit(k)) g.axis_k = k, g.axis_sign = g.normal[k] > 0 ? 1 : -1;
    std::sort(members.begin(), members.end());  // facet order within every cell
    Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (uint32_t f : members) {
      const Facet& fc = facets[f];
      const double pad = kGridPad + fc.flatness_m;
      lo = lo.cwiseMin(Eigen::Vector2d(fc.lo[g.axis_u], fc.lo[g.axis_v]) - Eigen::Vector2d::Constant(pad));
      hi = hi.cwiseMax(Eigen::Vector2d(fc.hi[g.axis_u], fc.hi[g.axis_v]) + Eigen::Vector2d::Constant(pad));
    }
    const double eu = std::max(hi.x() - lo.x(), 1e-6), ev = std::max(hi.y() - lo.y(), 1e-6);
    const double target = std::clamp(2.0 * static_cast<double>(members.size()), 1.0, 1048576.0);  // cells
    g.nu = static_cast<int>(std::clamp(std::round(std::sqrt(target * eu / ev)), 1.0, 8192.0));
    g.nv = static_cast<int>(std::clamp(std::ceil(target / g.nu), 1.0, 8192.0));
    g.u0 = lo.x();
    g.v0 = lo.y();
    g.inv_du = g.nu / eu;
    g.inv_dv = g.nv / ev;
    g.first_cell = static_cast<uint32_t>(cell_start_.size() - 1);
    // Counting sort of (cell, facet) pairs, facets ascending within each cell. A facet's bounds contain its
    // triangles' (which point_on_facet tests), padded by its flatness: the projection of a triangle along the
    // normal onto the facet's plane moves its corners by at most that.
    const size_t cells = static_cast<size_t>(g.nu) * g.nv;
    std::vector<uint32_t> count(cells + 1, 0);
    auto for_each_cell = [&](uint32_t f, auto&& fn) {
      const Facet& fc = facets[f];
      const double pad = kGridPad + fc.flatness_m;
      const auto cell = [](double x, double x0, double inv, int n) {
        return std::clamp(static_cast<int>(std::floor((x - x0) * inv)), 0, n - 1);
      };
      const int iu0 = cell(fc.lo[g.axis_u] - pad, g.u0, g.inv_du, g.nu), iu1 = cell(fc.hi[g.axis_u] + pad, g.u0, g.inv_du, g.nu);
      const int iv0 = cell(fc.lo[g.axis_v] - pad, g.v0, g.inv_dv, g.nv), iv1 = cell(fc.hi[g.axis_v] + pad, g.v0, g.inv_dv, g.nv);
      for (int iv = iv0; iv <= iv1; ++iv)
        for (int iu = iu0; iu <= iu1; ++iu) fn(static_cast<size_t>(iv) * g.nu + iu);
    };
    for (uint32_t f : members) for_each_cell(f, [&](size_t c) { ++count[c + 1]; });
    for (size_t c = 0; c < cells; ++c) count[c + 1] += count[c];
    const size_t base = cell_facets_.size();
    cell_facets_.resize(base + count[cells]);
    for (size_t c = 0; c < cells; ++c) cell_start_.push_back(static_cast<uint32_t>(base + count[c + 1]));
    std::vector<uint32_t> fill(count.begin(), count.end() - 1);
    // The occupancy bitmap: the same extent at ~64 cells per member (at most 2^22 per group), a bit set where
    // a member's padded bounds reach. One bit answers "no facet near P" for most groups of a link.
    const double bits = std::clamp(64.0 * static_cast<double>(members.size()), 1.0, 4194304.0);
    g.bnu = static_cast<int>(std::clamp(std::round(std::sqrt(bits * eu / ev)), 1.0, 16384.0));
    g.bnv = static_cast<int>(std::clamp(std::ceil(bits / g.bnu), 1.0, 16384.0));
    g.binv_du = g.bnu / eu;
    g.binv_dv = g.bnv / ev;
    g.first_bit = exact_bits_.size() * 64;
    exact_bits_.resize(exact_bits_.size() + (static_cast<size_t>(g.bnu) * g.bnv + 63) / 64, 0);
    for (uint32_t f : members) {
      const Facet& fc = facets[f];
      const double pad = kGridPad + fc.flatness_m;
      const auto cell = [](double x, double x0, double inv, int n) {
        return std::clamp(static_cast<int>(std::floor((x - x0) * inv)), 0, n - 1);
      };
      const int iu0 = cell(fc.lo[g.axis_u] - pad, g.u0, g.binv_du, g.bnu), iu1 = cell(fc.hi[g.axis_u] + pad, g.u0, g.binv_du, g.bnu);
      const int iv0 = cell(fc.lo[g.axis_v] - pad, g.v0, g.binv_dv, g.bnv), iv1 = cell(fc.hi[g.axis_v] + pad, g.v0, g.binv_dv, g.bnv);
      for (int iv = iv0; iv <= iv1; ++iv)
        for (int iu = iu0; iu <= iu1; ++iu) {
          const size_t bit = g.first_bit + static_cast<size_t>(iv) * g.bnu + iu;
          exact_bits_[bit / 64] |= uint64_t{1} << (bit % 64);
        }
    }
    for (uint32_t f : members) {
      // The facet's bounds in (u, v) as floats rounded outwards past inside_box's tolerance, so the scan
      // rejects most facets of a cell without touching their planes.
      const Facet& fc = facets[f];
      const auto down = [](double x) { return std::nextafter(static_cast<float>(x - 2e-6), -INFINITY); };
      const auto up = [](double x) { return std::nextafter(static_cast<float>(x + 2e-6), INFINITY); };
      const CellEntry e{down(fc.lo[g.axis_u]), up(fc.hi[g.axis_u]), down(fc.lo[g.axis_v]), up(fc.hi[g.axis_v]), f};
      for_each_cell(f, [&](size_t c) { cell_facets_[base + fill[c]++] = e; });
    }
    exact_groups_.push_back(g);
  }
  plane_box_.resize(facets.size());
  for (size_t f = 0; f < facets.size(); ++f)
    plane_box_[f] = {facets[f].normal, facets[f].offset_m, facets[f].lo, facets[f].hi};
  if (cell_facets_.size() > std::numeric_limits<uint32_t>::max())
    throw InputError("scene: too many triangles for the exact reflection search's grid");
}

void PathFinder::build_full_rects() {
  const auto& facets = scene_->facets();
  full_rect_.assign(facets.size(), 0);
  struct Uv {
    double u, v;
  };
  // Facets are independent: in parallel (each writes only its own flag).
  const auto n = static_cast<std::ptrdiff_t>(facets.size());
#pragma omp parallel if (n >= 4096 && !omp_in_parallel())
  {
    std::vector<std::array<Uv, 3>> tri;
    std::vector<std::pair<Uv, Uv>> edges;
#pragma omp for schedule(static)
    for (std::ptrdiff_t f = 0; f < n; ++f) {
      const Facet& fc = facets[f];
      int k = -1;
      for (int a = 0; a < 3; ++a)
        if (std::abs(fc.normal[a]) == 1.0) k = a;
      if (k < 0 || fc.triangles.empty()) continue;
      const int u = (k + 1) % 3, v = (k + 2) % 3;
      const double c = scene_->corners(fc.mesh, fc.triangles.front())[0][k];
      double ulo = INFINITY, uhi = -INFINITY, vlo = INFINITY, vhi = -INFINITY;
      bool planar = true;
      tri.clear();
      for (uint32_t t : fc.triangles) {
        const auto cs = scene_->corners(fc.mesh, t);
        std::array<Uv, 3> q;
        for (int j = 0; j < 3; ++j) {
          planar = planar && cs[j][k] == c;
          q[j] = {cs[j][u], cs[j][v]};
          ulo = std::min(ulo, q[j].u), uhi = std::max(uhi, q[j].u), vlo = std::min(vlo, q[j].v), vhi = std::max(vhi, q[j].v);
        }
        tri.push_back(q);
      }
      // (fc.lo/hi are these bounds; the fast path compares against them)
      if (!planar || !(ulo < uhi && vlo < vhi) || ulo != fc.lo[u] || uhi != fc.hi[u] || vlo != fc.lo[v] ||
          vhi != fc.hi[v])
        continue;
      edges.clear();
      for (const auto& q : tri)
        for (int j = 0; j < 3; ++j) {
          Uv a = q[j], b = q[(j + 1) % 3];
          if (std::tie(b.u, b.v) < std::tie(a.u, a.v)) std::swap(a, b);
          edges.push_back({a, b});
        }
      const auto key = [](const std::pair<Uv, Uv>& e) { return std::tie(e.first.u, e.first.v, e.second.u, e.second.v); };
      std::sort(edges.begin(), edges.end(), [&](const auto& x, const auto& y) { return key(x) < key(y); });
      bool sides_only = true;
      for (size_t i = 0; i < edges.size() && sides_only;) {
        size_t j = i + 1;
        while (j < edges.size() && key(edges[j]) == key(edges[i])) ++j;
        if ((j - i) % 2 == 1) {
          const Uv a = edges[i].first, b = edges[i].second;
          sides_only = (a.u == ulo && b.u == ulo) || (a.u == uhi && b.u == uhi) || (a.v == vlo && b.v == vlo) ||
                       (a.v == vhi && b.v == vhi);
        }
        i = j;
      }
      if (!sides_only) continue;
      // Covering parity at a sample point strictly inside (not within rounding of any triangle's edge).
      static constexpr double kSamples[4][2] = {{0.5, 0.5}, {0.31, 0.67}, {0.73, 0.29}, {0.53, 0.41}};
      for (const auto& sf : kSamples) {
        const Uv s{ulo + sf[0] * (uhi - ulo), vlo + sf[1] * (vhi - vlo)};
        int count = 0;
        bool ambiguous = false;
        for (const auto& q : tri) {
          bool pos = false, neg = false, near = false;
          for (int j = 0; j < 3; ++j) {
            const Uv a = q[j], b = q[(j + 1) % 3];
            const double eu = b.u - a.u, ev = b.v - a.v;
            const double e = eu * (s.v - a.v) - ev * (s.u - a.u);
            const double scale = std::sqrt(eu * eu + ev * ev) * ((uhi - ulo) + (vhi - vlo));
            if (std::abs(e) <= 1e-12 * scale) near = true;
            else (e > 0 ? pos : neg) = true;
          }
          if (pos && neg) continue;
          if (near) {
            ambiguous = true;
            break;
          }
          ++count;
        }
        if (!ambiguous) {
          full_rect_[f] = count % 2 == 1;
          break;
        }
      }
    }
  }
}

void PathFinder::reflections_exact(const Endpoint& ant, const Endpoint& tag, double f,
                                   const std::vector<uint32_t>* groups, std::vector<TracedPath>& out) const {
  struct Candidate {
    uint32_t facet;
    Vec3 image, p;
  };
  thread_local std::vector<Candidate> tl_found;  // per-thread scratch: no allocation once warm
  std::vector<Candidate>& found = tl_found;
  found.clear();
  const auto& facets = scene_->facets();
  const Vec3& a = ant.pose.position;
  const Vec3& t = tag.pose.position;
  const double eps = options_.surface_epsilon_m;
  // Three passes over the groups, so the memory reads of one (occupancy bit, cell range, cell entries) are
  // issued for every group before any is waited for: the search is bound by those reads, not by arithmetic.
  struct Window {
    uint32_t group;
    int iu0, iu1, iv0, iv1;     // cells of the facet grid
    double pu0, pu1, pv0, pv1;  // where P can be, in (u, v)
    size_t bit;                 // the occupancy bit under the window's low corner (SIZE_MAX: test none)
  };
  // Sized for every group once per thread; pass 1 fills it in place (a window is copied only when pass 2 keeps it).
  thread_local std::vector<Window> tl_windows;
  std::vector<Window>& windows = tl_windows;
  if (windows.size() < exact_groups_.size()) windows.resize(exact_groups_.size());
  size_t window_count = 0;
  Vec3 image, p, image2, p2;
  const size_t group_count = groups ? groups->size() : exact_groups_.size();
  for (size_t j = 0; j < group_count; ++j) {
    const uint32_t gi = groups ? (*groups)[j] : static_cast<uint32_t>(j);
    const ExactGroup& g = exact_groups_[gi];
    // A plane n·x = c rejects the link (image_point) iff c is within eps of the band between n·a and n·t.
    // Every member inside the band (with a margin for rounding): nothing here.
    const double na = g.normal.dot(a), nt = g.normal.dot(t);
    constexpr double kRound = 1e-9;
    if (g.offset_lo_m > std::min(na, nt) - eps + kRound && g.offset_hi_m < std::max(na, nt) + eps - kRound) continue;
    // Otherwise, where any member's image point can be: between those of the extreme planes (padded by the
    // span, the most the plane's own offset moves P along an axis). Unknown if either extreme rejects the
    // link (some member may not): then every cell of the group.
    Window& w = windows[window_count];
    w = Window{gi, 0, g.nu - 1, 0, g.nv - 1, -INFINITY, INFINITY, -INFINITY, INFINITY, SIZE_MAX};
    bool bounded = false;
    if (g.axis_sign != 0 && g.span_m <= 1e-6) {
      // Axis-aligned plane (the common case): P in (u, v) is a + s·(t − a), s = da/(da + dt), in a few
      // flops. The window only has to contain every member's P: pad it by the first-order motion of P over
      // the span, |ds/dc|·|t − a| per axis with |ds/dc| = |da − dt|/(da + dt)², doubled, plus 1e-7 m for
      // rounding (facets are binned and entries bounded with 2e-6 m more than inside_box accepts).
      const double da = g.axis_sign * a[g.axis_k] - g.offset_lo_m, dt = g.axis_sign * t[g.axis_k] - g.offset_lo_m;
      const double sum = da + dt;
      if (da * dt > 0.0 && std::abs(sum) > 1e3 * g.span_m) {
        const double sf = da / sum, motion = 2.0 * g.span_m * std::abs(da - dt) / (sum * sum);
        const double du = t[g.axis_u] - a[g.axis_u], dv = t[g.axis_v] - a[g.axis_v];
        const double pu = a[g.axis_u] + sf * du, pv = a[g.axis_v] + sf * dv;
        const double padu = motion * std::abs(du) + 1e-7, padv = motion * std::abs(dv) + 1e-7;
        w.pu0 = pu - padu, w.pu1 = pu + padu, w.pv0 = pv - padv, w.pv1 = pv + padv;
        bounded = true;
      }
    }
    if (!bounded && image_point(g.normal, g.offset_lo_m, a, t, eps, image, p) &&
        (g.span_m == 0.0 ? (p2 = p, true) : image_point(g.normal, g.offset_hi_m, a, t, eps, image2, p2))) {
      const double pad = g.span_m + 1e-9;
      w.pu0 = std::min(p[g.axis_u], p2[g.axis_u]) - pad, w.pu1 = std::max(p[g.axis_u], p2[g.axis_u]) + pad;
      w.pv0 = std::min(p[g.axis_v], p2[g.axis_v]) - pad, w.pv1 = std::max(p[g.axis_v], p2[g.axis_v]) + pad;
      bounded = true;
    }
    if (bounded) {
      const double ulo = (w.pu0 - g.u0) * g.inv_du, uhi = (w.pu1 - g.u0) * g.inv_du;
      const double vlo = (w.pv0 - g.v0) * g.inv_dv, vhi = (w.pv1 - g.v0) * g.inv_dv;
      if (!(uhi >= 0.0 && vhi >= 0.0 && ulo < g.nu && vlo < g.nv)) continue;  // off every facet
      // (its cells, iu0 … iv1, only for the windows pass 2 keeps)
      // The occupancy bit under the window, when the window is within one bit (almost always).
      // (the window meets the grid, so clamping at 0 before truncating is the floor, clamped)
      const int bu0 = static_cast<int>(std::max((w.pu0 - g.u0) * g.binv_du, 0.0));
      const int bu1 = static_cast<int>(std::min((w.pu1 - g.u0) * g.binv_du, g.bnu - 1.0));
      const int bv0 = static_cast<int>(std::max((w.pv0 - g.v0) * g.binv_dv, 0.0));
      const int bv1 = static_cast<int>(std::min((w.pv1 - g.v0) * g.binv_dv, g.bnv - 1.0));
      if (bu0 == bu1 && bv0 == bv1) {
        w.bit = g.first_bit + static_cast<size_t>(bv0) * g.bnu + bu0;
        __builtin_prefetch(&exact_bits_[w.bit / 64]);
      }
    }
    ++window_count;
  }
  // Pass 2: drop windows on an empty bit; the cells of the others (a bounded window's, from its bounds), and
  // ask for their ranges.
  size_t kept = 0;
  for (size_t i = 0; i < window_count; ++i) {
    Window& w = windows[i];
    if (w.bit != SIZE_MAX && !((exact_bits_[w.bit / 64] >> (w.bit % 64)) & 1u)) continue;
    const ExactGroup& g = exact_groups_[w.group];
    if (std::isfinite(w.pu0)) {
      // (the window meets the grid: clamping at 0 before truncating is the floor, clamped)
      const double ulo = (w.pu0 - g.u0) * g.inv_du, uhi = (w.pu1 - g.u0) * g.inv_du;
      const double vlo = (w.pv0 - g.v0) * g.inv_dv, vhi = (w.pv1 - g.v0) * g.inv_dv;
      w.iu0 = static_cast<int>(std::max(ulo, 0.0)), w.iu1 = static_cast<int>(std::min(uhi, g.nu - 1.0));
      w.iv0 = static_cast<int>(std::max(vlo, 0.0)), w.iv1 = static_cast<int>(std::min(vhi, g.nv - 1.0));
    }
    __builtin_prefetch(&cell_start_[g.first_cell + static_cast<size_t>(w.iv0) * g.nu + w.iu0]);
    if (kept != i) windows[kept] = w;
    ++kept;
  }
  // Pass 3: the cells' facets, each with reflections_exhaustive's tests, in its order, on the facet's own plane
  // (bitwise copies of it).
  for (size_t i = 0; i < kept; ++i) {
    const Window& w = windows[i];
    const ExactGroup& g = exact_groups_[w.group];
    for (int iv = w.iv0; iv <= w.iv1; ++iv)
      for (int iu = w.iu0; iu <= w.iu1; ++iu) {
        const size_t c = g.first_cell + static_cast<size_t>(iv) * g.nu + iu;
        for (uint32_t k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
          const CellEntry& e = cell_facets_[k];
          if (w.pu1 < e.u_lo || w.pu0 > e.u_hi || w.pv1 < e.v_lo || w.pv0 > e.v_hi) continue;  // fails inside_box
          const PlaneBox& b = plane_box_[e.facet];
          if (!image_point(b.normal, b.offset_m, a, t, eps, image, p) || (image - a).squaredNorm() > max_length2_ ||
              !inside_box(p, b.lo, b.hi, 1e-6))
            continue;
          // On a facet that covers its bounding rectangle, inside the closed rectangle means on the facet.
          const bool in_rect = !full_rect_.empty() && full_rect_[e.facet] && p[g.axis_u] >= b.lo[g.axis_u] && p[g.axis_u] <= b.hi[g.axis_u] &&
                               p[g.axis_v] >= b.lo[g.axis_v] && p[g.axis_v] <= b.hi[g.axis_v];
          if (!in_rect && !point_on_facet(facets[e.facet], p)) continue;
          found.push_back({e.facet, image, p});
        }
      }
  }
  // reflections_exhaustive's order (the de-duplication of coplanar facets keeps the first); a facet binned in
  // several cells of the window is taken once.
  std::sort(found.begin(), found.end(), [](const Candidate& x, const Candidate& y) { return x.facet < y.facet; });
  found.erase(std::unique(found.begin(), found.end(),
                          [](const Candidate& x, const Candidate& y) { return x.facet == y.facet; }),
              found.end());
  for (const Candidate& c : found)
    add_reflection(c.facet, c.image, c.p, ant, tag, f, /*check_leg1=*/true, out);
}

void PathFinder::exact_groups_near(const Vec3& a, const Vec3& lo, const Vec3& hi, std::vector<uint32_t>& out) const {
  out.clear();
  const double eps = options_.surface_epsilon_m;
  constexpr double kRound = 1e-9;  // reflections_exact's
  for (uint32_t gi = 0; gi < exact_groups_.size(); ++gi) {
    const ExactGroup& g = exact_groups_[gi];
    // Only axis-aligned groups are judged for the whole box (their n·x is one coordinate, exactly); any
    // other is searched for every link. NaN anywhere makes every test below false: the group is kept.
    if (g.axis_sign == 0) {
      out.push_back(gi);
      continue;
    }
    const int k = g.axis_k, u = g.axis_u, v = g.axis_v;
    const double na = g.axis_sign * a[k];  // = g.normal.dot(a) bitwise: the other components are ±0
    const double nt_lo = g.axis_sign > 0 ? lo[k] : -hi[k], nt_hi = g.axis_sign > 0 ? hi[k] : -lo[k];
    // reflections_exact's first test with the extreme n·t of the box: its two sides are non-decreasing in n·t
    // (rounding is monotone), so true at both ends means true for every tag of the box.
    if (g.offset_lo_m > std::min(na, nt_hi) - eps + kRound && g.offset_hi_m < std::max(na, nt_lo) + eps - kRound)
      continue;
    // Otherwise only where every tag takes the axis-aligned window (both endpoints strictly on one side, far
    // from a thin group): P = a + s (t − a), s = da / (da + dt), bounded over the box by its corners (N/D with
    // D of one sign is monotone in N and in D), plus the largest window padding, 2 span |du| / |D| + 1e-7
    // (|da − dt| ≤ |da + dt| on one side), plus a rounding margin far above the few roundings per link.
    if (g.span_m > 1e-6) {
      out.push_back(gi);
      continue;
    }
    const double da = na - g.offset_lo_m;
    const double dt_lo = nt_lo - g.offset_lo_m, dt_hi = nt_hi - g.offset_lo_m;
    constexpr double kTiny = 1e-150;  // da · dt cannot underflow to 0
    const bool one_side = (da > kTiny && dt_lo > kTiny) || (da < -kTiny && dt_hi < -kTiny);
    if (!(one_side && std::abs(da) > 1e3 * g.span_m)) {
      out.push_back(gi);
      continue;
    }
    const double d_lo = da + dt_lo, d_hi = da + dt_hi;
    const double d_min = std::min(std::abs(d_lo), std::abs(d_hi));
    double region[2][2];  // [axis u, v][low, high]
    for (int axis = 0; axis < 2; ++axis) {
      const int c = axis == 0 ? u : v;
      const double n_lo = lo[c] - a[c], n_hi = hi[c] - a[c];
      const double q[4] = {da * n_lo / d_lo, da * n_lo / d_hi, da * n_hi / d_lo, da * n_hi / d_hi};
      const double du_max = std::max(std::abs(n_lo), std::abs(n_hi));
      const double margin = 2.0 * g.span_m * du_max / d_min + 1e-7 + 1e-9 + 1e-12 * (std::abs(a[c]) + du_max + 1.0);
      region[axis][0] = a[c] + *std::min_element(q, q + 4) - margin;
      region[axis][1] = a[c] + *std::max_element(q, q + 4) + margin;
    }
    // Off the grid on either axis for every tag: reflections_exact skips the group for each.
    const double u1 = g.u0 + g.nu / g.inv_du, v1 = g.v0 + g.nv / g.inv_dv;
    const auto beyond = [](double x, double end) { return x > end + 1e-9 * (std::abs(end) + 1.0); };
    if (region[0][1] < g.u0 || region[1][1] < g.v0 || beyond(region[0][0], u1) || beyond(region[1][0], v1)) continue;
    // Every occupancy bit under the region empty: no facet of the group is near any tag's reflection point.
    const auto bit_cell = [](double x, double x0, double inv, int n) {
      return static_cast<int>(std::clamp(std::floor((x - x0) * inv), 0.0, n - 1.0));
    };
    const int bu0 = bit_cell(region[0][0], g.u0, g.binv_du, g.bnu), bu1 = bit_cell(region[0][1], g.u0, g.binv_du, g.bnu);
    const int bv0 = bit_cell(region[1][0], g.v0, g.binv_dv, g.bnv), bv1 = bit_cell(region[1][1], g.v0, g.binv_dv, g.bnv);
    // (A region of more than 4096 bits is kept unscanned: it is seldom empty.)
    const bool occupied = any_bit_in_rect(exact_bits_, g.first_bit, g.bnu, bu0, bu1, bv0, bv1);
    if (occupied) out.push_back(gi);
  }
}

void PathFinder::reflections_by_plane(const Endpoint& ant, const Endpoint& tag, double f, const PoseCandidates& c,
                                  const std::vector<uint32_t>* exact_groups, std::vector<TracedPath>& out) const {
  if (c.all) {
    reflections_exact(ant, tag, f, exact_groups, out);
  } else {
    for (uint32_t g : c.planes) try_plane(g, ant, tag, f, c, out);
  }
}

void PathFinder::try_plane(uint32_t group, const Endpoint& ant, const Endpoint& tag, double f,
                           const PoseCandidates& c, std::vector<TracedPath>& out) const {
  const PlaneGroup& g = planes_[group];
  const Vec3& a = ant.pose.position;
  Vec3 image, p;
  if (!image_point(g.normal, g.offset_m, a, tag.pose.position, options_.surface_epsilon_m, image, p)) return;
  if ((image - a).squaredNorm() > max_length2_) return;  // longer than max_path_length_m
  const size_t bit = cell_bit(g, p);
  if (bit == SIZE_MAX) return;
  // (Candidate rays only: the exact mode is reflections_exact.) A point no candidate ray saw is taken as
  // hidden from the antenna (seen cells are occupied ones).
  if (!((c.seen_cells[bit / 64] >> (bit % 64)) & 1u)) return;
  // One ray A→P answers both "is leg 1 clear" and "which facet of this plane is at P": the first thing hit
  // must be a facet of this plane.
  const Vec3 d1 = p - a;
  const double l1 = d1.norm();
  const Vec3 dir1 = d1 / l1;
  const double margin = plane_margin(options_.surface_epsilon_m + g.flatness_m, std::abs(dir1.dot(g.normal)), l1);
  const RayHit h = scene_->bvh().intersect(a, dir1, std::min(options_.endpoint_epsilon_m, 0.25 * l1), l1 + margin);
  if (!h.hit) return;
  const uint32_t facet = scene_->facet_of(scene_->triangle_id(h.geom, h.prim));
  if (facet == kNoFacet || plane_of_facet_[facet] != group) return;
  // Redo the image in the facet's own plane (identical to the group's within the grouping tolerance).
  const Facet& fc = scene_->facets()[facet];
  if (!image_point(fc.normal, fc.offset_m, a, tag.pose.position, options_.surface_epsilon_m, image, p)) return;
  add_reflection(facet, image, p, ant, tag, f, /*check_leg1=*/false, out);
}

void PathFinder::add_reflection(uint32_t facet, const Vec3& image, const Vec3& p, const Endpoint& ant,
                                const Endpoint& tag, double f, bool check_leg1, std::vector<TracedPath>& out) const {
  // A thin post's faces are not mirrors at the levels that model it (raytrace/post_scattering.cpp).
  if (is_post_facet(facet)) return;
  const Facet& fc = scene_->facets()[facet];
  const Vec3& a = ant.pose.position;
  const Vec3& t = tag.pose.position;
  // Coplanar facets meeting along an edge both contain a P on that edge: count the reflection once.
  for (const TracedPath& q : out)
    if (q.kind == PathKind::kReflection && (q.point - p).norm() < 1e-7 &&
        std::abs(scene_->facets()[q.facet].normal.dot(fc.normal)) > 1.0 - 1e-9)
      return;
  const Vec3 d1 = p - a, d2 = t - p;
  const double l1 = d1.norm(), l2 = d2.norm();
  if (!(l1 > 0.0) || !(l2 > 0.0)) return;
  ++tl_mirror_points;
  const Vec3 dir1 = d1 / l1, dir2 = d2 / l2;
  const double cos_theta = std::abs(dir1.dot(fc.normal));
  const double clearance = options_.surface_epsilon_m + fc.flatness_m;  // legs stay clear of the facet itself
  const EmbreeScene& bvh = scene_->bvh();
  const double end_eps1 = std::min(options_.endpoint_epsilon_m, 0.25 * l1);
  const double end_eps2 = std::min(options_.endpoint_epsilon_m, 0.25 * l2);
  // Both legs must be clear, so the order changes only the number of rays: the longer leg first (it crosses
  // more of the scene, so it is the more often blocked one, and a blocked leg ends the test). The covered
  // rectangles (no ray; true only where the Embree ray would be blocked) are asked about both legs first.
  const double leg1_far = l1 - plane_margin(clearance, cos_theta, l1);
  const double leg2_near = plane_margin(clearance, cos_theta, l2), leg2_far = l2 - end_eps2;
  if (covered_) {
    const auto culled1 = [&] { return check_leg1 && covered_->blocks(a, dir1, end_eps1, leg1_far); };
    const auto culled2 = [&] { return covered_->blocks(p, dir2, leg2_near, leg2_far); };
    if (l2 > l1 ? culled2() || culled1() : culled1() || culled2()) {
      ++tl_segments_culled;
      return;
    }
  }
  // Leg 1 is shot from the reflection point back to the antenna: Embree's float ray is exact to a few ulps of its
  // origin's coordinates, and precision matters next to the facet (an antenna 50 km away has 4 mm ulps, which
  // would put the leg's far end through the facet it leaves: issue #33's lost reflection of a distant source).
  const auto leg1_blocked = [&] {
    return check_leg1 && bvh.occluded(p, -dir1, plane_margin(clearance, cos_theta, l1), l1 - end_eps1);
  };
  const auto leg2_blocked = [&] { return bvh.occluded(p, dir2, leg2_near, leg2_far); };
  if (l2 > l1 ? leg2_blocked() || leg1_blocked() : leg1_blocked() || leg2_blocked()) return;
  ++tl_reflections_found;

  const RadioMaterial& m = scene_->materials()[fc.material];
  const double gain = std::sqrt(ant.pattern.gain_linear_world(ant.pose.orientation, dir1) *
                                tag.pattern.gain_linear_world(tag.pose.orientation, -dir2));
  const CVec3 incident = ant.polarization.field(ant.pose.orientation, dir1);
  const CVec3 reflected = reflect_field(incident, dir1, fc.normal, material_reflection(m, f, cos_theta));
  TracedPath path;
  path.kind = PathKind::kReflection;
  path.length_m = (image - a).norm();
  path.point = p;
  path.material = fc.material;
  path.facet = facet;
  path.coefficient = gain * polarization_match(reflected, tag.polarization, tag.pose.orientation, dir2);
  path.contribution = path_contribution(path.length_m, path.coefficient, f);
  out.push_back(path);
}

Path PathFinder::to_path(const TracedPath& p) const {
  Path out;
  out.kind = p.kind;
  out.length_m = p.length_m;
  out.point = p.point;
  if (p.material != kNoMaterial) out.material = scene_->materials()[p.material].name;
  if (p.kind == PathKind::kReflection2 || p.kind == PathKind::kDiffraction2) {
    out.point2 = p.point2;
    if (p.material2 != kNoMaterial) out.material2 = scene_->materials()[p.material2].name;
  }
  out.crossings = p.crossings;
  out.coefficient = p.coefficient;
  out.contribution = p.contribution;
  return out;
}

}  // namespace rfidray
