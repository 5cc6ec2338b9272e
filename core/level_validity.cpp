#include "core/level_validity.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <tuple>
#include <utility>

#include "core/edge_near_field.h"
#include "core/units.h"
#include "core/wedge_series.h"

namespace rfidray {
namespace {

// Each end's nearest edge within reach, lit from the other end: the nearer one first (the tag's on a tie).
std::pair<std::optional<EdgeSight>, std::optional<EdgeSight>> both_ends_edges(const Channel& channel,
                                                                                const Endpoint& antenna,
                                                                                const Endpoint& tag,
                                                                                double frequency_hz) {
  const double reach = level_validity_reach_m(frequency_hz);
  std::optional<EdgeSight> at_tag = channel.nearest_edge(tag, antenna, reach);
  std::optional<EdgeSight> at_antenna = channel.nearest_edge(antenna, tag, reach);
  if (at_antenna && (!at_tag || at_antenna->distance_m < at_tag->distance_m)) return {at_antenna, at_tag};
  return {at_tag, at_antenna};
}

constexpr double kReachKrho = 9.0;

// What the canonical check cannot see, measured: `full` (with the edge's near field) against the FDTD reference
// round two finite sheets lit from 1 m, 0.9 × 0.8 m and 0.9 × 1.6 m (bench/results/fullwave/sheet_edge*.csv and
// sheet_edge.md: 11 angles at each of ρ = 4, 8, 16, 32 cm; reference converged to ≤ 0.03, 2026-12-07). It is the floor
// of a diffracting level's estimate, split as the incident field is.
//
// Along the edge (soft) what is left is small and flat: the medians per band of kρ over both sheets' 22 observers
// (0.017–0.026 on the shorter sheet, 0.007–0.010 on the taller one).
struct SoftBand {
  double krho_max;
  double error;
};
constexpr SoftBand kSoftBands[] = {
    {1.1, 0.011},
    {2.2, 0.010},
    {4.4, 0.012},
    {kReachKrho, 0.019},
};
// Across the edge (hard) what is left is the plate, not the edge: the same edge, source and observers with the
// sheet twice as tall move the FDTD field by 0.1–0.26 of the free-space field, and `full`, whose canonical near field
// is an infinite half-plane's, by at most 0.02 (docs/fullwave.md, "What is left across an edge"). The error has the
// size and direction of the edge's singular near field, (kρ)^{1/n − 1} along ê_s (core/edge_sight.h; Meixner's edge
// condition: the edge charge a finite plate sets differently), as the end's antenna reads it (singular_share): on
// the 0.8 m sheet at ρ = 4 cm, error / ((kρ)^{−1/2}·singular_share) is 0.15–0.18 at all 11 angles. The scale is
// that ratio's 75th percentile over both sheets' 88 observers; on a right-angled wedge (case wedge_edge_hard, not
// used to set it) the same ratio's 75th percentile is 0.153.
constexpr double kHardEdgeChargeScale = 0.144;

double full_wave_floor(double krho, double soft_share, double n, double singular_share) {
  const SoftBand* band = kSoftBands;
  while (krho > band->krho_max && band + 1 != std::end(kSoftBands)) ++band;
  const double s = std::clamp(soft_share, 0.0, 1.0);
  // kρ ≥ 1e-3 keeps the estimate finite on the edge itself (it is far outside any level's validity there).
  const double hard = kHardEdgeChargeScale * std::pow(std::max(krho, 1e-3), 1.0 / std::clamp(n, 1.0, 2.0) - 1.0) *
                      std::clamp(singular_share, 0.0, 1.0);
  return s * band->error + std::sqrt(1.0 - s * s) * hard;
}

// The measured errors of each level in the geometries the canonical wedge does not cover: medians of the
// per-observer errors |h/h_ideal − E/E_free| of the FDTD cases (bench/results/fullwave/CASE.csv, regions as in
// bench/results/fullwave/other_geometries.md; meep, Richardson extrapolated, spread ≤ 0.05 at every observer).
// `diffracting`: full-selective and full; `rays`: los+blocked, single-bounce and double-bounce (los has no
// transmission or reflection: a blocked link has no path there, flagged by `link` as such).
struct MeasuredError {
  double diffracting;
  double rays;
};
// upright.csv, "behind, on the axis" (the 5 cm post blocks the direct line; no level has a path): 0.44 at every
// level.
constexpr MeasuredError kNarrowBlocking{0.44, 0.44};
// upright.csv, "behind, 10 cm aside" (the direct line passes 5–7 cm from the post): full 0.25, single-bounce 0.51.
constexpr MeasuredError kNarrowBeside{0.25, 0.51};
// The same two regions at full-selective and full with the post modelled as a cylinder (raytrace/thin_posts.h):
// E along the post (upright.csv) behind 0.07, aside 0.06 (medians of 4 observers each; max 0.08 / 0.09); E across it
// (upright_hard.csv) 0.04 and 0.04 (max 0.155 / 0.07). The larger median of the two polarizations.
constexpr double kModelledPostBlocking = 0.07;
constexpr double kModelledPostBeside = 0.06;
// An end closer to the post than kρ = 1.5 (8 cm at 866 MHz): the worst measured there, E across the post 5 cm behind
// it (kρ = 1.0): 0.155 (E along it: 0.06). The obstacle check does not know the polarization: the larger.
constexpr double kModelledPostNear = 0.155;
// An end near a modelled post but off the direct line (rack_post.csv, "beside the post, in front of the shelves":
// full 0.046, 0.063, 0.070, 0.100 at kρ 1.4–3.2 from the post; median 0.07. With first-order diffraction only it
// was 0.053–0.135, median 0.11).
constexpr double kModelledPostOffLine = 0.07;
constexpr double kModelledPostNearKrho = 1.5;
// concrete_wall.csv, "behind (transmission)": full 0.15, los+blocked / single-bounce / double-bounce 0.11.
constexpr MeasuredError kSlabTransmission{0.15, 0.11};
// concrete_wall.csv and doorway.csv, the 24 observers beyond the wall's front plane (rfidray's sheet) within
// 0.75 m of its outline or its opening: full median 0.28 (19 of 24 above 0.1), los+blocked 0.24 (21 of 24).
constexpr MeasuredError kBeyondSlabEdge{0.28, 0.24};
// rack_bay.csv: "inside (between the plates)" full 0.05 (max 0.16), the others 0.14; "outside (in front of the bay)"
// full 0.07 (max 0.12), the others 0.05. With first-order diffraction only full was 0.17 and 0.12: the second-order
// diffraction between the plates' edges (raytrace/double_diffraction.cpp) is what brings it within 0.1.
constexpr MeasuredError kPlatesInside{0.05, 0.14};
constexpr MeasuredError kPlatesInFront{0.07, 0.05};
constexpr MeasuredError kPlatesInsideFirstOrder{0.17, 0.14};  // double_diffraction_max_m below the gap (or 0)
constexpr MeasuredError kPlatesInFrontFirstOrder{0.12, 0.05};

// plate_grazing.csv, plate_corner_line.csv and plate_corner.csv, the 15 observers whose link sees a plate edge-on
// (EdgeOnPlate): full 0.029–0.338, bimodal (8 at 0.03–0.07 beside the plate's edges, 7 at 0.14–0.34 farther beyond
// it or past a corner), so the median (0.069) would pass the seven; the estimate is the 75th percentile, 0.17. The
// levels without diffraction: median 0.996 (the direct ray blocked where the field is nearly the free-space one).
constexpr MeasuredError kEdgeOnPlate{0.17, 0.996};

std::string centimetres(double m) {
  char b[32];
  std::snprintf(b, sizeof b, "%.1f cm", 100.0 * m);
  return b;
}

void set_error(LevelValidity& v, double error, double relative_amplitude) {
  v.estimated_error = error;
  const double r = error / std::max(relative_amplitude, 1e-12);
  // Capped at 40 dB: a level whose |h| is far below its own error (a shadowed link without diffraction) has no
  // meaningful dB figure; the fraction says it.
  v.estimated_error_db = std::min(20.0 * std::log10(1.0 + r), 40.0);
  v.estimated_error_rad = std::asin(std::min(r, 1.0));
}

void append(std::string& reason, const std::string& more) { reason += (reason.empty() ? "" : "; ") + more; }

}  // namespace

double level_validity_reach_m(double frequency_hz) { return kReachKrho / wavenumber_rad_m(frequency_hz); }

CanonicalErrors canonical_edge_errors(const EdgeSight& sight, double frequency_hz) {
  const double n = std::clamp(sight.n, 1.0, 2.0);
  const double phi = std::clamp(sight.phi_rad, 0.0, n * kPi);
  const double phi_prime = std::clamp(sight.phi_prime_rad, 0.0, n * kPi);
  // Oblique incidence: the transverse problem has wavenumber k·sin β0 (Keller's cone); the axial phase is common.
  const double k_t = wavenumber_rad_m(frequency_hz) * std::clamp(sight.sin_beta0, 0.0, 1.0);
  const double rho = std::clamp(sight.distance_m, 0.0, 200.0 / std::max(k_t, 1e-300));
  const WedgeField exact = wedge_plane_wave_exact(n, rho, phi, phi_prime, k_t);
  const WedgeField go = wedge_plane_wave_geometrical_optics(n, rho, phi, phi_prime, k_t);
  const WedgeField utd = wedge_plane_wave_utd(n, rho, phi, phi_prime, k_t);
  const auto hard = [&](const WedgeField& u) {
    return std::hypot(std::abs(u.hard_e_rho - exact.hard_e_rho), std::abs(u.hard_e_phi - exact.hard_e_phi));
  };
  const double s = std::clamp(sight.soft_share, 0.0, 1.0), h = std::sqrt(1.0 - s * s);
  CanonicalErrors e;
  e.geometrical_optics_soft = std::abs(go.soft - exact.soft);
  e.geometrical_optics_hard = hard(go);
  e.geometrical_optics = s * e.geometrical_optics_soft + h * e.geometrical_optics_hard;
  e.utd_soft = std::abs(utd.soft - exact.soft);
  e.utd_hard = hard(utd);
  e.utd = s * e.utd_soft + h * e.utd_hard;
  return e;
}

LevelValidity level_validity(ChannelLevel level, const std::optional<EdgeSight>& sight, double frequency_hz,
                             double relative_amplitude) {
  LevelValidity v;
  if (!sight || level == ChannelLevel::kIdeal) return v;
  const double k = wavenumber_rad_m(frequency_hz);
  v.nearest_edge_m = sight->distance_m;
  v.nearest_edge_krho = k * sight->distance_m;
  const bool diffracts = includes(level, ChannelLevel::kFullSelective);
  const CanonicalErrors canonical = canonical_edge_errors(*sight, frequency_hz);
  // Levels full and full-selective add the edge's near field (core/edge_near_field.h) with weight w: what is left is
  // (1 − w) of UTD's canonical error. (full-selective leaves out at most 0.02 of |h| besides: the weakest
  // diffractions, never a near edge's, which is among the strongest; below what this estimate resolves.)
  const double w = diffracts
                       ? edge_near_field_weight(k * sight->sin_beta0 * sight->distance_m,
                                                sight->other_distance_m / std::max(sight->distance_m, 1e-12),
                                                sight->sin_beta0)
                       : 0.0;
  const double floor =
      diffracts ? full_wave_floor(v.nearest_edge_krho, sight->soft_share, sight->n, sight->singular_share) : 0.0;
  set_error(v, diffracts ? std::max((1.0 - w) * canonical.utd, floor) : canonical.geometrical_optics,
            relative_amplitude);
  char b[400];
  char shape[48];
  if (sight->n > 2.0 - 1e-6)
    std::snprintf(shape, sizeof shape, "a sheet's edge");
  else
    std::snprintf(shape, sizeof shape, "a %.0f° wedge", (2.0 - sight->n) * 180.0);
  const bool measured = diffracts && floor >= (1.0 - w) * canonical.utd;
  std::snprintf(b, sizeof b, "an end %s from an edge (%s, kρ = %.2f, %.0f %% of the field across the edge): %s "
                "%.3f of the free-space field there (%s)",
                centimetres(sight->distance_m).c_str(), shape, v.nearest_edge_krho,
                100.0 * (1.0 - sight->soft_share * sight->soft_share),
                measured    ? "measured against FDTD beside a finite sheet, full is off by"
                : diffracts ? "rays with UTD are off by"
                            : "without diffraction this level is off by",
                v.estimated_error, measured ? "docs/fullwave.md" : "exact wedge series");
  v.reason = b;
  v.level_ok = v.estimated_error <= kLevelErrorLimit;
  // What the canonical check does not cover: flagged, with the canonical error as a lower bound.
  if (sight->second_edge_m && k * *sight->second_edge_m < kNearEdgeKrho) {
    v.level_ok = false;
    append(v.reason, "a second edge " + centimetres(*sight->second_edge_m) +
                         " away (a corner or a narrow plate): the two edges interact (full diffracts twice only "
                         "between edges λ/2 or more apart, and no level diffracts at corners), not checked here; the "
                         "error is at least the above");
  }
  if (k * sight->other_distance_m < kNearEdgeKrho) {
    v.level_ok = false;
    append(v.reason, "the other end is " + centimetres(sight->other_distance_m) +
                         " from the same edge: the plane-wave check does not hold; the error is not known");
  }
  if (!sight->metal_faces && diffracts)
    append(v.reason, "the edge's faces are not metal: UTD with Luebbers' heuristic coefficients, checked against "
                     "the exact series for metal only");
  if (!v.level_ok && v.estimated_error <= kLevelErrorLimit) append(v.reason, "outside what was checked");
  else if (!v.level_ok) append(v.reason, "outside the level's validity");
  return v;
}

LinkSight link_sight(const Channel& channel, const Endpoint& antenna, const Endpoint& tag, double frequency_hz) {
  LinkSight sight;
  std::tie(sight.edge, sight.edge_other_end) = both_ends_edges(channel, antenna, tag, frequency_hz);
  sight.obstacles = channel.obstacle_sight(antenna, tag, frequency_hz);
  return sight;
}

LevelValidity level_validity(ChannelLevel level, const LinkSight& sight, double frequency_hz,
                             double relative_amplitude) {
  LevelValidity v = level_validity(level, sight.edge, frequency_hz, relative_amplitude);
  if (level == ChannelLevel::kIdeal) return v;
  const bool diffracts = includes(level, ChannelLevel::kFullSelective);
  double worst = v.estimated_error;
  bool flagged = false;
  // `what`, then how far off the level is there: measured (against FDTD, the default) or estimated.
  const auto add = [&](double error, const std::string& what, const char* measured_or_estimated = ": measured") {
    char b[80];
    std::snprintf(b, sizeof b, "%s off by %.2f of the free-space field", measured_or_estimated, error);
    append(v.reason, what + b);
    worst = std::max(worst, error);
    flagged |= error > kLevelErrorLimit;
  };
  const auto pick = [&](const MeasuredError& m) { return diffracts ? m.diffracting : m.rays; };
  if (sight.edge_other_end) {
    const LevelValidity other = level_validity(level, sight.edge_other_end, frequency_hz, relative_amplitude);
    if (!other.level_ok || other.estimated_error > worst) {
      append(v.reason, "at the other end, " + other.reason);
      worst = std::max(worst, other.estimated_error);
      flagged |= !other.level_ok;
    }
  }
  const ObstacleSight& o = sight.obstacles;
  // A modelled post off the direct line is a near-field matter of the levels that model it only.
  if (o.narrow && !(o.narrow->off_line && !diffracts)) {
    char b[300];
    std::snprintf(b, sizeof b, "a narrow obstacle (two edges %s apart, %s from %s) %s: rays and single-edge "
                  "diffraction do not describe an object that small (FDTD behind a 5 cm upright, docs/fullwave.md)",
                  centimetres(o.narrow->width_m).c_str(), centimetres(o.narrow->distance_m).c_str(),
                  o.narrow->at_end ? "an end" : "where metal blocks the direct line",
                  o.narrow->blocks ? "blocks the direct line"
                                   : ("passes " + centimetres(o.narrow->clearance_m) + " from the direct line, within its Fresnel zone (" +
                                      centimetres(o.narrow->fresnel_radius_m) + ")").c_str());
    if (o.narrow->modelled_post && diffracts) {
      const bool near = o.narrow->at_end && wavenumber_rad_m(frequency_hz) * o.narrow->distance_m < kModelledPostNearKrho;
      std::snprintf(b, sizeof b, "a thin metal post (%s across, %s from %s) %s: modelled as a circular cylinder "
                    "(FDTD round a 5 cm upright and a rack post, docs/fullwave.md)%s",
                    centimetres(o.narrow->width_m).c_str(), centimetres(o.narrow->distance_m).c_str(),
                    o.narrow->at_end ? "an end" : "where it crosses the direct line",
                    o.narrow->blocks ? "on the direct line" : o.narrow->off_line ? "off the direct line, its near field reaching the end" : "beside the direct line",
                    near ? "; closer than kρ = 1.5, where with E across the post it is the least sure" : "");
      add(near               ? kModelledPostNear
          : o.narrow->off_line ? kModelledPostOffLine
          : o.narrow->blocks   ? kModelledPostBlocking
                               : kModelledPostBeside,
          b);
    } else {
      add(pick(o.narrow->blocks ? kNarrowBlocking : kNarrowBeside), b);
    }
  }
  if (o.slab) {
    char b[300];
    std::snprintf(b, sizeof b, "the direct line crosses a penetrable slab %s from its edge (knife-edge ν = %.1f): "
                  "the slab's edges diffract a field the transmission model %s (FDTD behind a concrete wall, "
                  "docs/fullwave.md)",
                  centimetres(o.slab->edge_distance_m).c_str(), o.slab->fresnel_nu,
                  diffracts ? "misses or gets wrong (UTD with heuristic coefficients)" : "leaves out");
    add(pick(kSlabTransmission), b);
  }
  if (o.beyond_slab_edge)
    add(pick(kBeyondSlabEdge),
        "an end behind a penetrable slab, " + centimetres(o.beyond_slab_edge->distance_m) +
            " from its edge or opening: the slab is a zero-thickness sheet with a transmission coefficient to every "
            "level, and what passes a thick wall's edge or doorway is not modelled (FDTD behind a concrete wall and a "
            "doorway, docs/fullwave.md)");
  if (o.plates) {
    const bool twice = o.plates->second_order_diffraction;
    add(pick(o.plates->inside ? (twice ? kPlatesInside : kPlatesInsideFirstOrder)
                              : (twice ? kPlatesInFront : kPlatesInFrontFirstOrder)),
        std::string("an end ") + (o.plates->inside ? "between" : "just in front of") + " two parallel metal plates " +
            centimetres(o.plates->gap_m) + " apart: bounces between the plates and their edges interact (FDTD " +
            (o.plates->inside ? "inside" : "in front of") + " a rack bay, docs/fullwave.md)");
  }
  if (o.edge_on_plate) {
    char b[400];
    const EdgeOnPlate& p = *o.edge_on_plate;
    std::snprintf(b, sizeof b, "a metal plate seen edge-on: two of its edges %s apart along the direct line and %s "
                  "across it, both within its Fresnel zone (%s from the line, zone radius %s): rays see two opaque "
                  "half-planes where FDTD finds such a plate nearly invisible with E normal to it (docs/fullwave.md)",
                  centimetres(p.along_m).c_str(), centimetres(p.across_m).c_str(), centimetres(p.clearance_m).c_str(),
                  centimetres(p.fresnel_radius_m).c_str());
    add(pick(kEdgeOnPlate), b);
  }
  if (o.edge_end && diffracts) {
    char b[400];
    const EdgeEnd& end = *o.edge_end;
    std::snprintf(b, sizeof b, "a diffraction point %s %s an edge's end, within its Fresnel zone (half-width %s): "
                  "the edge's term (%.2f of the free-space field) is computed for an infinite edge and dropped past "
                  "the end, where the edge carries a share of it (docs/fullwave.md, \"Where `full` is "
                  "discontinuous\")",
                  centimetres(std::abs(end.past_end_m)).c_str(), end.past_end_m > 0.0 ? "past" : "inside",
                  centimetres(end.fresnel_half_width_m).c_str(), end.term_share);
    add(end.estimated_error, b, "; estimated");
  }
  if (worst > v.estimated_error) set_error(v, worst, relative_amplitude);
  if (flagged && v.level_ok) {
    v.level_ok = false;
    append(v.reason, "outside the level's validity");
  }
  return v;
}

std::optional<EdgeSight> link_edge_sight(const Channel& channel, const Endpoint& antenna, const Endpoint& tag,
                                         double frequency_hz) {
  return both_ends_edges(channel, antenna, tag, frequency_hz).first;
}

std::optional<ChannelLevel> judged_level(const Channel& channel) {
  const std::string name = channel.name();
  const std::optional<ChannelLevel> level = parse_channel_level(std::string_view(name));
  if (!level || *level == ChannelLevel::kIdeal) return std::nullopt;
  return level;
}

LevelValidity with_reference_error(LevelValidity v, double error_vs_reference, double relative_amplitude,
                                   const std::string& reference_name) {
  if (!(error_vs_reference > v.estimated_error)) return v;
  set_error(v, error_vs_reference, relative_amplitude);
  if (v.estimated_error > kLevelErrorLimit) v.level_ok = false;
  char b[200];
  const bool said = v.reason.find("outside the level's validity") != std::string::npos;
  std::snprintf(b, sizeof b, "differs from %s on this link by %.3f of the free-space field%s", reference_name.c_str(),
                error_vs_reference, v.level_ok || said ? "" : ": outside the level's validity");
  append(v.reason, b);
  return v;
}

}  // namespace rfidray
