#include "raytrace/raytraced_channel.h"

#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>
#include <omp.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <complex>
#include <mutex>
#include <stdexcept>

#include "core/level_validity.h"
#include "core/polarization.h"
#include "raytrace/edge_end_finder.h"
#include "raytrace/edge_on_plate_finder.h"
#include "raytrace/morton.h"
#include "raytrace/obstacle_finder.h"

namespace rfidray {

namespace {
// The calling thread's tracer counters (rays, culled legs, mirror points, reflections found, plane pairs
// tried), which a threaded batch credits to its caller.
constexpr size_t kCounters = 6;
std::array<uint64_t*, kCounters> thread_counters() {
  return {&tl_rays_traced,       &tl_segments_culled,   &tl_mirror_points,
          &tl_reflections_found, &tl_plane_pairs_tried, &tl_edge_pair_orders_tried};
}
}  // namespace

RaytracedChannel::RaytracedChannel(std::shared_ptr<const Scene> scene, const TraceOptions& options)
    : finder_(std::move(scene), options) {
  // Width 0 = "time the widths on the first pose"; single rays unless the user opted in (trace_options.h).
  if (!options.los_packets_by_timing) los_packet_width_.store(1, std::memory_order_relaxed);
}

void RaytracedChannel::set_los_packet_width(int width) {
  if (width != 1 && width != 4 && width != 8 && width != 16)
    throw std::invalid_argument("los packet width must be 1, 4, 8 or 16 (got " + std::to_string(width) + ")");
  los_packet_width_.store(width, std::memory_order_relaxed);
}

std::vector<Path> RaytracedChannel::paths(const Endpoint& antenna, const Endpoint& tag, double frequency_hz) const {
  PoseCandidates candidates;
  finder_.prepare_pose(antenna.pose.position, candidates);
  std::vector<TracedPath> traced;
  finder_.trace(antenna, tag, frequency_hz, candidates, traced);
  std::vector<Path> out;
  out.reserve(traced.size());
  for (const TracedPath& p : traced) out.push_back(finder_.to_path(p));
  return out;
}

int fastest_los_packet_width(const PathFinder& finder, const Endpoint& antenna, std::span<const Endpoint> tags,
                             std::span<const uint32_t> order) {
  std::vector<Segment> seg;
  const Vec3& a = antenna.pose.position;
  for (size_t i = 0; i < order.size() && seg.size() < 512; ++i) {
    const Vec3& t = tags[order[i]].pose.position;
    Segment s;
    if (all_finite(a) && all_finite(t) && (t - a).norm() > 0.0 && finder.direct_segment(a, t, s)) seg.push_back(s);
  }
  if (seg.empty() || finder.scene().empty()) return 1;
  const uint64_t rays_before = tl_rays_traced;
  const std::unique_ptr<bool[]> blocked(new bool[seg.size()]);
  constexpr int kWidths[] = {1, 4, 8, 16};
  double best[4] = {INFINITY, INFINITY, INFINITY, INFINITY};
  for (int round = 0; round < 5; ++round)
    for (int j = 0; j < 4; ++j) {
      const int w = round % 2 ? 3 - j : j;  // alternate the order, so no width always runs first
      const auto t0 = std::chrono::steady_clock::now();
      finder.scene().bvh().occluded_many(kWidths[w], seg.data(), seg.size(), blocked.get());
      best[w] = std::min(best[w], std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
  tl_rays_traced = rays_before;
  // Packets only when clearly faster (by a quarter): near the crossover the choice would flip between runs,
  // and the one case where packet and single-ray answers differ (a ray lying in a triangle's plane) would
  // follow it.
  const int packet = static_cast<int>(std::min_element(best + 1, best + 4) - best);
  return best[packet] * 1.25 < best[0] ? kWidths[packet] : 1;
}

// one_way's chunk of tags: 16, the exact search's and double-bounce's block (path_finder.h).
constexpr size_t kOneWayChunk = 16;

// Threads pay from 64 tags up to single-bounce, where a link costs 0.2–16 µs: a few chunks are less work than
// starting the lanes. From double-bounce up a link costs ≥ ~75 µs (the paper warehouse; 43 ms at full on w1m:
// bench_levels, 2026-12-07), so two chunks already pay.
size_t RaytracedChannel::threaded_batch_min_tags() const {
  return includes(finder_.options().level, ChannelLevel::kDoubleBounce) ? kOneWayChunk + 1 : 64;
}

void RaytracedChannel::one_way(const Endpoint& antenna, std::span<const Endpoint> tags, double frequency_hz,
                               std::span<std::complex<double>> h) const {
  // The caller's scratch, reused across calls. Bound to plain references: inside a parallel loop a
  // thread_local name would denote each worker's own copy.
  thread_local PoseCandidates tl_candidates;
  thread_local std::vector<uint64_t> tl_keys, tl_new_keys;
  thread_local std::vector<std::pair<uint64_t, uint32_t>> tl_sorted;
  thread_local std::vector<uint32_t> tl_order;
  PoseCandidates& candidates = tl_candidates;
  std::vector<uint32_t>& order = tl_order;
  finder_.prepare_pose(antenna.pose.position, candidates);
  const size_t n = tags.size();
  // Tags in spatial (Morton) order, so consecutive links traverse the same part of the BVH and hit warm
  // caches; every link is computed on its own, so the order changes nothing but speed. The order depends on
  // the keys alone: the same keys as the last call, the same order (no sort per pose over static tags).
  std::vector<uint64_t>& keys = tl_new_keys;
  keys.resize(n);
  for (size_t i = 0; i < n; ++i) keys[i] = morton_key(tags[i].pose.position);
  if (keys != tl_keys || order.size() != n) {
    tl_keys.swap(keys);
    std::vector<std::pair<uint64_t, uint32_t>>& sorted = tl_sorted;
    sorted.resize(n);
    for (size_t i = 0; i < n; ++i) sorted[i] = {tl_keys[i], static_cast<uint32_t>(i)};
    std::sort(sorted.begin(), sorted.end());
    order.resize(n);
    for (size_t i = 0; i < n; ++i) order[i] = sorted[i].second;
  }
  finder_.decide_plane_pair_sharing(antenna.pose.position, tags, order, candidates);
  finder_.decide_edge_pair_sharing(antenna.pose.position, tags, order, candidates);
  int width = 1;
  if (finder_.options().level == ChannelLevel::kLos) {
    width = los_packet_width_.load(std::memory_order_relaxed);
    if (width == 0 && n >= 64) {
      width = fastest_los_packet_width(finder_, antenna, tags, order);
      int expected = 0;  // the first measurement wins (concurrent first poses)
      if (!los_packet_width_.compare_exchange_strong(expected, width, std::memory_order_relaxed)) width = expected;
    }
    width = std::max(width, 1);
  }
  const int threads = omp_in_parallel() ? 1 : std::max(1, omp_get_max_threads());
  if (threads < 2 || n < threaded_batch_min_tags()) {
    finder_.trace_sum(antenna, tags, order, frequency_hz, candidates, width, h);
    return;
  }
  thread_local std::unique_ptr<tbb::task_arena> tl_arena;
  if (!tl_arena || tl_arena->max_concurrency() != threads) tl_arena = std::make_unique<tbb::task_arena>(threads);
  // Rays traced (and the other thread_counters()) by whichever thread runs a chunk are credited to the
  // caller, so counts summed over the caller's threads stay what a serial loop gives.
  std::array<std::atomic<uint64_t>, kCounters> credited{};
  std::mutex error_mutex;
  std::exception_ptr error;
  const std::span<const uint32_t> all(order);
  // Chunks of 16 tags starting at multiples of 16 (the packets are the serial loop's at any thread count),
  // handed out one at a time from a shared counter to one lane per thread. A lane that starts late (a
  // worker woken from sleep, or descheduled) finds fewer chunks or none, and the caller waits at most for
  // the chunks already taken: a work-stealing split of the range itself would hand the first thief half of
  // it, and the caller would wait for that half however late the thief started.
  const size_t chunks = (n + kOneWayChunk - 1) / kOneWayChunk;
  std::atomic<size_t> next{0};
  const auto lane = [&] {
    const std::array<uint64_t*, kCounters> counters = thread_counters();
    std::array<uint64_t, kCounters> before;
    for (size_t k = 0; k < kCounters; ++k) before[k] = *counters[k];
    for (size_t c; (c = next.fetch_add(1, std::memory_order_relaxed)) < chunks;) {
      const size_t first = c * kOneWayChunk, last = std::min(n, first + kOneWayChunk);
      try {
        finder_.trace_sum(antenna, tags, all.subspan(first, last - first), frequency_hz, candidates, width, h);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        next.store(chunks, std::memory_order_relaxed);  // stop handing out chunks
      }
    }
    for (size_t k = 0; k < kCounters; ++k) {
      credited[k].fetch_add(*counters[k] - before[k], std::memory_order_relaxed);
      *counters[k] = before[k];
    }
  };
  tl_arena->execute([&] {
    tbb::task_group lanes;
    for (int k = 1; k < threads; ++k) lanes.run(lane);
    lane();
    lanes.wait();  // runs any lane no worker took (it finds no chunk left)
  });
  const std::array<uint64_t*, kCounters> counters = thread_counters();
  for (size_t k = 0; k < kCounters; ++k) *counters[k] += credited[k].load();
  if (error) std::rethrow_exception(error);
}

std::optional<NearbySurface> RaytracedChannel::nearest_surface(const Vec3& point, double max_distance_m) const {
  const auto s = scene().nearest_surface(point, max_distance_m);
  if (!s) return std::nullopt;
  const RadioMaterial& m = scene().materials()[s->material];
  return NearbySurface{s->distance_m, m, s->facet_extent_m, s->faces_facet};
}

const EdgeProximity& RaytracedChannel::edge_index() const {
  constexpr double kIndexRadius_m = 0.75;  // level_validity_reach_m at UHF is ~0.5 m
  std::call_once(edge_index_once_, [&] {
    edge_index_ = std::make_unique<EdgeProximity>(finder_.edges().empty() ? extract_edges(scene()) : finder_.edges(),
                                                  kIndexRadius_m);
  });
  return *edge_index_;
}

ObstacleSight RaytracedChannel::obstacle_sight(const Endpoint& antenna, const Endpoint& tag, double frequency_hz) const {
  ObstacleSight o = find_obstacles(scene(), edge_index(), antenna.pose.position, tag.pose.position, frequency_hz,
                                   level_validity_reach_m(frequency_hz), finder_.options().surface_epsilon_m,
                                   finder_.post_of_edge());
  if (o.plates) o.plates->second_order_diffraction = finder_.options().double_diffraction_max_m >= o.plates->gap_m;
  o.edge_end = find_edge_end(finder_, antenna, tag, frequency_hz);
  o.edge_on_plate = find_edge_on_plate(scene(), edge_index(), antenna.pose.position, tag.pose.position, frequency_hz,
                                       finder_.post_of_edge());
  return o;
}

std::optional<EdgeSight> RaytracedChannel::nearest_edge(const Endpoint& end_point, const Endpoint& other_point,
                                                        double max_distance_m) const {
  const Vec3& end = end_point.pose.position;
  const Vec3& other_end = other_point.pose.position;
  const EdgeProximity& index = edge_index();
  // Up to six: a thin box's corner has three edges on each face, and the two nearest may both be on the face that
  // the other end does not see (their wedges' interiors, extended, hold it), where the one that matters is next.
  std::array<EdgeProximity::Hit, 6> hits;
  index.nearest(end, hits);
  const auto post_of_edge = finder_.post_of_edge();
  const auto is_post_edge = [&](uint32_t e) { return !post_of_edge.empty() && post_of_edge[e] != kNoPost; };
  const auto& facets = scene().facets();
  const auto& materials = scene().materials();
  // The nearest edge that the two ends see from the same exterior region; the other hit, if any, is the second
  // edge near this end.
  for (size_t i = 0; i < hits.size(); ++i) {
    const EdgeProximity::Hit& hit = hits[i];
    if (hit.edge == kNoEdge || hit.distance_m > max_distance_m) break;
    // A thin post's edge, where the level models the post as a cylinder: not an edge to it (the post is judged as
    // a narrow obstacle, raytrace/obstacle_finder.h).
    if (is_post_edge(hit.edge)) continue;
    const Edge& e = index.edge(hit.edge);
    const Vec3 r_end = end - e.start, r_other = other_end - e.start;
    const Vec3 v_end = r_end - r_end.dot(e.direction) * e.direction;
    const Vec3 v_other = r_other - r_other.dot(e.direction) * e.direction;
    WedgeAngles w;
    if (v_end.norm() < 1e-9 || v_other.norm() < 1e-9 || !wedge_angles(e, v_other, v_end, w)) continue;
    EdgeSight sight;
    sight.distance_m = hit.distance_m;
    sight.n = w.n;
    sight.phi_rad = w.phi_rad;
    sight.phi_prime_rad = w.phi_prime_rad;
    // The diffraction point (Fermat: it divides the feet's span in the ratio of the distances) and the incident
    // ray's direction there; its polarization split as in raytrace/diffraction.cpp.
    const double rho_end = v_end.norm(), rho_other = v_other.norm();
    const double z_end = r_end.dot(e.direction), z_other = r_other.dot(e.direction);
    const Vec3 q = e.start + (z_other + (z_end - z_other) * rho_other / (rho_other + rho_end)) * e.direction;
    const Vec3 s_in = (q - other_end).normalized();
    sight.sin_beta0 = s_in.cross(e.direction).norm();
    if (sight.sin_beta0 > 1e-9) {
      const Vec3 phi_in = -(e.direction.cross(s_in)).normalized();
      const Vec3 beta_in = phi_in.cross(s_in);
      const CVec3 e_in = other_point.polarization.field(other_point.pose.orientation, s_in);
      const double soft = std::abs(beta_in.cast<std::complex<double>>().dot(e_in));
      const double hard = std::abs(phi_in.cast<std::complex<double>>().dot(e_in));
      if (soft + hard > 0.0) sight.soft_share = soft / std::hypot(soft, hard);
    }
    {
      // This end's reading of the edge's singular near field (core/edge_sight.h): φ grows about +e (raytrace/edges.h,
      // angle_about), so φ̂ = ê × ρ̂.
      const Vec3 rho_hat = v_end / rho_end;
      const Vec3 phi_hat = e.direction.cross(rho_hat);
      const Vec3 e_s = std::sin(w.phi_rad / w.n) * rho_hat + std::cos(w.phi_rad / w.n) * phi_hat;
      const Polarization& pol = end_point.polarization;
      sight.singular_share =
          pol.kind == PolarizationKind::kLinear
              ? std::abs((end_point.pose.orientation * pol.axis_local).normalized().dot(e_s))
              : std::abs(polarization_match(e_s.cast<std::complex<double>>(), pol, end_point.pose.orientation,
                                            (end - q).normalized()));
      if (!std::isfinite(sight.singular_share)) sight.singular_share = 1.0;  // no axis to read it by: assume all
    }
    sight.other_distance_m = v_other.norm();
    sight.metal_faces = materials[facets[w.face0].material].perfect_conductor &&
                        materials[facets[w.facen].material].perfect_conductor;
    // The second edge near this end: the nearest other one.
    for (size_t j = 0; j < hits.size(); ++j) {
      const EdgeProximity::Hit& other = hits[j];
      if (j == i || other.edge == kNoEdge || other.distance_m > max_distance_m || is_post_edge(other.edge)) continue;
      sight.second_edge_m = other.distance_m;
      break;
    }
    return sight;
  }
  return std::nullopt;
}

}  // namespace rfidray
