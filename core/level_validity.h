#pragma once
// Where a channel level can be trusted near a metal edge. A link's end a few centimetres from an edge sees the
// edge's near field: geometrical optics (levels without diffraction) is off there by up to the whole incident
// field, and UTD (levels full-selective and full) is an expansion in 1/(kρ). How far off each is, is measured
// here on the link's own geometry against the exact solution of the canonical problem: the perfectly conducting
// wedge of the nearest edge (its exterior angle), lit by a plane wave from the other end's direction, observed at
// this end's distance and angle (core/wedge_series.h, the eigenfunction series, exact at any kρ). The incident
// field is split as UTD splits it: along the edge (soft: ray optics is right to ~1e-2 down to kρ ≈ 0.25, and exact
// on a sheet's edge) and across it (hard: the electric field near the edge has a radial part growing as (kρ)^−½,
// which no ray carries; GO + UTD is off by ~0.38 of the incident field at kρ = 0.73, 0.10 at kρ = 2.9). Level full
// adds that near field (core/edge_near_field.h) where the canonical problem holds; its estimate is what the
// near field's weight leaves out, and never less than what the FDTD runs of bench/fullwave/ measured for `full`
// beside a finite sheet lit from 1 m (docs/fullwave.md: 0.03 along the edge, 0.12 / 0.10 / 0.04 / 0.04 across it
// at kρ ≤ 1.1 / 2.2 / 4.4 / 9).
//
// What that canonical check covers and what it does not (docs/fullwave.md, with the full-wave FDTD runs of
// bench/fullwave/ that check the geometries it leaves out):
//   - covered: one straight edge of a wedge or a sheet, faces of metal, the other end far from the edge;
//   - flagged, not covered: a second edge close to the same end (a corner, a narrow plate or a 3 cm shelf lip:
//     double diffraction, which `full` has only in UTD's form, not checked this close), the other end close to the same edge too (the incident wave is
//     not plane there), faces that are not metal (UTD with Luebbers' heuristic coefficients).
//   - judged from the FDTD runs of the geometries the wedge does not cover (core/obstacle_sight.h; the estimate is
//     the measured median error of the level there, bench/results/fullwave/CASE.csv): a narrow obstacle on or
//     beside the direct line (a 5 cm rack upright), the direct line through a penetrable slab near the slab's
//     edge and an end near a penetrable slab's edge beyond its plane (a concrete wall, a doorway), an end between
//     or just in front of two facing parallel metal plates (a rack bay);
//     A metal plate seen edge-on (two edges of one facet within the direct line's Fresnel zone, less than λ/2 apart
//     across it: a shelf at grazing), where FDTD finds the plate nearly invisible (raytrace/edge_on_plate_finder.h);
//   - estimated from the link's own edges (raytrace/edge_end_finder.h, diffracting levels only): a first-order
//     diffraction point within a Fresnel zone of its edge's end (a plate's corner), where the levels drop the
//     edge's term at the end and the field jumps.
// Errors are fractions of the free-space field (|h/h₀ − E/E₀|: the field at this end in units of the incident
// field at the edge, which is the free-space field when the other end is far). The verdict's dB and rad are what
// that error can do to a link whose |h/h₀| is given: 20·log10(1 + e/|h/h₀|) (at most 40) and
// asin(min(1, e/|h/h₀|)) (π/2 when the error reaches |h/h₀|, a phase that can be anything).
// A level is ok when its estimated error is ≤ kLevelErrorLimit (0.1 of the free-space field) and nothing
// uncovered was flagged. Pure functions: thread-safe, nothing throws.
#include <optional>
#include <string>

#include "core/channel.h"
#include "core/channel_level.h"
#include "core/edge_sight.h"

namespace rfidray {

inline constexpr double kLevelErrorLimit = 0.1;

struct LevelValidity {
  bool level_ok = true;
  std::string reason;                    // one line for the user; empty when ok and nothing to say
  double estimated_error = 0.0;          // fraction of the free-space field
  double estimated_error_db = 0.0;       // at this link's |h/h₀| (see above)
  double estimated_error_rad = 0.0;
  std::optional<double> nearest_edge_m;  // the nearer end's distance to an edge, when within reach
  double nearest_edge_krho = 0.0;        // k times it (0 when no edge is that close)
};

// How far from an edge the check looks: kρ = 9 (0.5 m at 866 MHz). Beyond, the diffracted field is a small
// share of the incident one except near shadow boundaries, which single-bounce and below miss at any distance
// (docs/physics.md says so) and full has (tests/raytrace/test_diffraction.cpp).
double level_validity_reach_m(double frequency_hz);

// Within this kρ of a second edge (or of the same edge, for the other end) the canonical check does not cover
// the link (see above): kρ = 3, where UTD's own terms are within ~1 % of the exact wedge.
inline constexpr double kNearEdgeKrho = 3.0;

// The canonical errors of geometrical optics and of GO + UTD for the wedge of `sight`, fractions of the incident
// field: soft |ΔE_z|; hard |ΔE| of the electric field (E_ρ and E_φ, where the edge's near field is); and the two
// weighted by the incident field's split, soft_share·soft + √(1 − soft_share²)·hard.
struct CanonicalErrors {
  double geometrical_optics_soft = 0.0, geometrical_optics_hard = 0.0, geometrical_optics = 0.0;
  double utd_soft = 0.0, utd_hard = 0.0, utd = 0.0;
};
CanonicalErrors canonical_edge_errors(const EdgeSight& sight, double frequency_hz);

// The verdict for `level` with the nearer end's edge `sight` (nullopt: no edge within reach of either end), for a
// link whose |h/h₀| is `relative_amplitude` (1 when unknown). Ideal is not judged (it ignores the scene).
LevelValidity level_validity(ChannelLevel level, const std::optional<EdgeSight>& sight, double frequency_hz,
                             double relative_amplitude = 1.0);

// The nearer end's edge of a link (antenna at `antenna`, tag at `tag`): each end's nearest edge within reach, lit
// from the other end (Channel::nearest_edge), and of the two the one with the smaller distance. Thread-safe when the
// channel is.
std::optional<EdgeSight> link_edge_sight(const Channel& channel, const Endpoint& antenna, const Endpoint& tag,
                                         double frequency_hz);

// Everything the verdict looks at on one link: the nearer end's edge, the other end's (when it has one within
// reach: an end farther from its edge can be the worse one, e.g. beside a corner) and the obstacles of the link.
struct LinkSight {
  std::optional<EdgeSight> edge;
  std::optional<EdgeSight> edge_other_end;
  ObstacleSight obstacles;
};

// link_edge_sight and Channel::obstacle_sight of the link. Thread-safe when the channel is.
LinkSight link_sight(const Channel& channel, const Endpoint& antenna, const Endpoint& tag, double frequency_hz);

// The verdict on the nearer end's edge (above; its distance is the verdict's nearest_edge_m), then on the other
// end's and on the obstacles: each adds its reason where it raises the estimate or flags the link (flagged when
// above kLevelErrorLimit or outside what was checked).
LevelValidity level_validity(ChannelLevel level, const LinkSight& sight, double frequency_hz,
                             double relative_amplitude = 1.0);

// The level a channel's verdicts are for: a traced level, known by the channel's name; nullopt for the ideal
// channel (it ignores the scene) and for a channel that is not a level (a test double), which are not judged.
std::optional<ChannelLevel> judged_level(const Channel& channel);

// The same verdict with a measured error added: `error_vs_reference` (a fraction of the free-space field) is the
// difference to a richer level computed on the same link (`link` compares with `full`). The larger of the two
// errors decides.
LevelValidity with_reference_error(LevelValidity v, double error_vs_reference, double relative_amplitude,
                                   const std::string& reference_name);

}  // namespace rfidray
