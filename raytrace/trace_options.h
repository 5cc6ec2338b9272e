#pragma once
// Settings of the ray-traced channel (raytrace/raytraced_channel.h).
#include <limits>
#include <string>

#include "core/channel_level.h"

namespace rfidray {


// How reflection candidates are searched. Both are exact: they find the same paths (tests/raytrace/
// test_exact_search.cpp); kExact is the default because it is the faster of the two.
enum class CandidateMode {
  kExhaustive,  // reference: every facet, point-in-triangle on its triangles, rtcOccluded1 on both legs
  kExact,       // the same paths as kExhaustive, found through per-plane grids (path_finder.h). Only
                // TraceOptions::candidate_rays > 0 (off by default) makes it approximate: planes grouped,
                // Embree says which facet is there
};

struct TraceOptions {
  ChannelLevel level = ChannelLevel::kSingleBounce;  // a traced level (is_traced)
  CandidateMode candidates = CandidateMode::kExact;
  // Exact mode, optional: shoot this many rays (spherical Fibonacci) from each antenna pose and test only the
  // parts of planes they hit. 0 = off (exact: every plane is tested). Reflections off regions the rays
  // missed (small or distant reflectors, slivers behind occluders) are lost when > 0.
  int candidate_rays = 0;
  // Footprint of each candidate ray on the surface it hits, in units of the ray spacing: the cells it covers
  // count as seen from the antenna (path_finder.h, PoseCandidates). Larger = fewer missed reflections, slower.
  double candidate_spread = 1.0;
  // Paths whose power is more than this many dB below the strongest path of the link are dropped.
  double drop_below_db = 40.0;
  // Paths longer than this (unfolded length) are not modelled; a direct path longer than it leaves the link
  // with no path (h = 0). Culls by range before any ray is shot (a reflection's length is known from its
  // image point). Infinite = off (exact).
  double max_path_length_m = std::numeric_limits<double>::infinity();
  // Rays stop this short of an antenna or tag, so a tag mounted on a surface is not occluded by it.
  double endpoint_epsilon_m = 1e-3;
  // Reflection legs are tested from this height above the reflecting plane (float-precision margin of
  // Embree; 100 µm ≈ λ/3500 at 866 MHz); crossings closer together than this count once.
  double surface_epsilon_m = 1e-4;
  // A direct path crossing more surfaces than this is dropped (its transmission is negligible anyway).
  int max_crossings = 16;
  // Level full-selective (raytrace/diffraction.cpp): the weakest diffracted paths are left out while the sum of
  // their magnitudes is at most this fraction ε of |h| of the paths kept, so |h_selective/h_full − 1| ≤ ε/(1 − ε):
  // at most 2·asin(ε/(1 − ε)) rad of round-trip phase and 40·log10(1/(1 − ε)) dB of RSSI (0.041 rad, 0.35 dB at
  // the default 0.02, inside `auto`'s default tolerance). 0 keeps every diffraction and near field (= full).
  double diffraction_skipped_fraction = 0.02;
  // Levels full-selective and full: metal posts whose cross-section is at most this wide (and 4× longer than
  // wide) scatter as circular cylinders (raytrace/thin_posts.h, post_scattering.cpp) instead of reflecting off
  // their faces and diffracting at their edges. 0.15 m ≈ 0.43 λ at 866 MHz: a rack upright (5–10 cm), not a
  // column. 0 = off (every post is faces and edges, as before).
  double thin_post_max_width_m = 0.15;
  // Levels full-selective and full: second-order diffraction (raytrace/double_diffraction.cpp) between two edges
  // (parallel ones, or two of one facet) where the leg between them is at most this long (metres): a shelf plate's
  // front and back edges (0.3–0.6 m deep), its side and back edges, the two plates of a bay. Relative to a single
  // diffraction the second one scales as 1/√(k·s12): beyond a few wavelengths it is small. 0 = off (first-order
  // diffraction only, as before).
  double double_diffraction_max_m = 1.0;
  // Level los: trace a pose's visibility rays in Embree packets (rtcOccluded4/8/16) when timing them on the
  // first pose shows a packet width ≥ 1.25× faster than single rays (raytraced_channel.h). Off by default:
  // Embree's packet and single-ray kernels disagree on some near-degenerate rays (a ray in a triangle's
  // plane, or one starting next to a surface — a tag mounted on a shelf), so a choice made by timing could
  // change such a link's result from one run to the next, and rfidray's output depends only on its inputs
  // and --seed. With it off every ray is rtcOccluded1, as before packets existed.
  bool los_packets_by_timing = false;
  // Exact mode: before a reflection leg's Embree ray, test it against the rectangles that the scene's
  // axis-aligned triangles cover entirely (raytrace/covered_rects.h); a leg crossing one is blocked for
  // certain and needs no ray. Changes the number of rays, never a path. Off by default: on the 1 M-triangle
  // warehouse it cuts the rays per link from 20.5 to ~3.3 but the grid walk costs more than the rays it saves
  // (README, #13); off, every leg is an Embree ray and nothing is built.
  bool cull_covered = false;
  // Level double-bounce, links traced together (one_way): the plane pairs each block of 16 nearby tags can
  // use are found once and shared by its links (PathFinder::plane_pairs_near). Changes the work, never a
  // path. kAuto shares where a probe of the pose's first block says it pays (fewer than 0.42 of all pairs
  // kept; ≥ 64 tags); kAlways and kNever are for tests and benchmarks.
  enum class Sharing { kAuto, kAlways, kNever };
  Sharing plane_pair_sharing = Sharing::kAuto;
  // Levels full-selective and full, links traced together: the orders of edge pairs (second-order diffraction) each
  // block of 16 nearby tags can use are found once and shared by its links (PathFinder::edge_pairs_near). Changes
  // the work, never a path; kAuto as above, with its own measured threshold (PathFinder::decide_edge_pair_sharing).
  Sharing edge_pair_sharing = Sharing::kAuto;
};

// "exhaustive" | "exact"
const char* to_string(CandidateMode mode);
// "exhaustive" | "exact"; "fast", the name of kExact before it was called exact, is accepted as an alias so that
// older scenario files and commands keep working. Throws InputError naming `field` otherwise.
CandidateMode parse_candidate_mode(const std::string& name, const std::string& field);

}  // namespace rfidray
