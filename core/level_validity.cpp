#include "core/level_validity.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/edge_near_field.h"
#include "core/units.h"
#include "core/wedge_series.h"

namespace rfidray {
namespace {

constexpr double kReachKrho = 9.0;

// What the canonical check cannot see, measured: `full` (with the edge's near field) against the FDTD reference
// round a finite 0.9 × 0.8 m sheet lit from 1 m (bench/results/fullwave/sheet_edge.md, median over 11 angles per
// distance; the reference's own spread is 0.03 soft and 0.07 hard there). A spherical source, the sheet's other
// edges and corners leave this much; it is the floor of a diffracting level's estimate, by the incident field's
// split.
struct FullWaveBand {
  double krho_max;
  double soft_error;
  double hard_error;
};
constexpr FullWaveBand kFullWaveBands[] = {
    {1.1, 0.028, 0.138},
    {2.2, 0.032, 0.121},
    {4.4, 0.029, 0.055},
    {kReachKrho, 0.035, 0.045},
};

double full_wave_floor(double krho, double soft_share) {
  const FullWaveBand* band = kFullWaveBands;
  while (krho > band->krho_max && band + 1 != std::end(kFullWaveBands)) ++band;
  const double s = std::clamp(soft_share, 0.0, 1.0);
  return s * band->soft_error + std::sqrt(1.0 - s * s) * band->hard_error;
}

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
  // Level full adds the edge's near field (core/edge_near_field.h) with weight w: what is left is (1 − w) of UTD's
  // canonical error. full-selective has no near-field term.
  const double w = level == ChannelLevel::kFull
                       ? edge_near_field_weight(k * sight->sin_beta0 * sight->distance_m,
                                                sight->other_distance_m / std::max(sight->distance_m, 1e-12),
                                                sight->sin_beta0)
                       : 0.0;
  const double floor = diffracts ? full_wave_floor(v.nearest_edge_krho, sight->soft_share) : 0.0;
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
                         " away (a corner or a narrow plate): double diffraction, which no level has, is not checked "
                         "here; the error is at least the above");
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

std::optional<EdgeSight> link_edge_sight(const Channel& channel, const Endpoint& antenna, const Endpoint& tag,
                                         double frequency_hz) {
  const double reach = level_validity_reach_m(frequency_hz);
  std::optional<EdgeSight> at_tag = channel.nearest_edge(tag, antenna, reach);
  std::optional<EdgeSight> at_antenna = channel.nearest_edge(antenna, tag, reach);
  if (at_tag && at_antenna) return at_antenna->distance_m < at_tag->distance_m ? at_antenna : at_tag;
  return at_tag ? at_tag : at_antenna;
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
