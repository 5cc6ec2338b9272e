#pragma once
// The edge-end check of core/obstacle_sight.h (EdgeEnd) for one link, from the diffracting levels' own edges: for
// every edge whose Keller point lies within four Fresnel half-widths of an end (on the edge or past it), the
// infinite edge's first-order UTD term as a share of the free-space field, r·max(|D_s|, |D_h|)/√(s s' (s + s'))
// (core/utd.h: the field ratio of the diffracted to the direct ray, r = |antenna − tag|, with the ends' patterns
// towards the Keller point and along the direct line), times
// |step − T|: the difference between what the levels do (the whole term while the point is on the edge, none past
// it) and the uniform asymptotic evaluation of the edge integral ∫ f(z) e^{−jkL(z)} dz, f = 1/(s s') (the incident
// field times a line source's spreading, times the ends' pattern amplitudes along the path), relative to its stationary-phase value (the infinite edge's term):
// with τ(z) = sign(z − z_Q)·√(k (L(z) − L(z_Q))) and g(z) = f(z)/f(z_Q) · (dz/dτ)(z)/(dz/dτ)(z_Q),
//   T = [G(τ₁) − G(τ₀) + h(τ₁) − h(τ₀)] / (√π e^{−jπ/4}),  G(a) = ∫_{−∞}^a e^{−jτ²} dτ,  h(τ) = (g − 1) e^{−jτ²}/(−2jτ)
// (a stationary point near an endpoint: the Fresnel integral, then integration by parts at the ends to first order;
// N. Bleistein, R. A. Handelsman, "Asymptotic Expansions of Integrals", 1975),
// L(z) the path length antenna → edge point z → tag (the exact detour, not its quadratic), ends z = 0 and L_e. The
// term's UTD coefficient is taken at z_Q all along (conservative near a boundary, where it is largest there).
// Beyond four half-widths |step − T| is about 0.04 or less (the Fresnel tail there), below what is reported for any term share up to 1. The legs of the
// reported edge's point (on the edge, or its nearer end when the point is past it) must be clear.
// Cost: one pass over the edges with a few flops each (no square root for an edge far from its ends); for those
// near an end, T only where the bound of D (core/utd.h: 1/(2√(πX)) per term) times a bound of |step − T|
// (edge_truncation_deficit_bound: with no pattern evaluated, at the ends' largest pattern gains, then at their own)
// lets the estimate reach what is reported or the worst so far, UTD coefficients only where that bound times
// |step − T| does, two rays for the worst. The edge the calling thread reported last is tried first (its estimate
// then lets the bounds skip more); the result is the same in any order (the lowest-indexed edge of largest estimate).
// Units: metres, hertz. Thread-safe (reads the scene; one thread_local edge index); nothing throws.
#include <complex>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "core/channel.h"
#include "core/geometry.h"
#include "core/obstacle_sight.h"

namespace rfidray {

class PathFinder;

// The link's most uncertain edge end, when its estimate is ≥ kEdgeEndReported; nullopt when the finder has no edges
// (levels without diffraction) or none is that uncertain.
std::optional<EdgeEnd> find_edge_end(const PathFinder& finder, const Endpoint& antenna, const Endpoint& tag,
                                     double frequency_hz);

// The same result with every edge near an end evaluated in full, in index order: none of find_edge_end's bounds,
// its square-root-free test or the edge it tries first (the edge its thread reported last). For tests: what those
// skips must reproduce exactly. Many times slower.
std::optional<EdgeEnd> find_edge_end_without_skips(const PathFinder& finder, const Endpoint& antenna,
                                                   const Endpoint& tag, double frequency_hz);

// For tests: for each edge near an end whose estimate is computed (in find_edge_end_without_skips), the values
// find_edge_end compares before it instead, each of which must be at least the estimate (+∞ where X_min is 0), and
// whether its square-root-free test keeps the edge (it must).
struct EdgeEndCheck {
  uint32_t edge = 0;
  bool quick_test_keeps = false;
  double bound_without_patterns = 0.0, bound_at_largest_weight = 0.0, bound_at_end_weights = 0.0;
  double bound_with_integral = 0.0, estimate = 0.0;
};
std::vector<EdgeEndCheck> edge_end_checks(const PathFinder& finder, const Endpoint& antenna, const Endpoint& tag,
                                          double frequency_hz);

// The share T of an edge integral's stationary value that the edge [0, length_m] along `start` + z·`direction`
// carries for the path antenna → edge → tag (see above). 1 for a Keller point deep inside, ½ at an end.
// `end_weight(z)`, when given, is the ends' antenna and tag pattern amplitudes √(G_R G_T) along the path via edge point
// z relative to via the Keller point (f is multiplied by it; 1 when absent: isotropic ends).
std::complex<double> edge_truncation(const Vec3& start, const Vec3& direction, double length_m, const Vec3& antenna,
                                     const Vec3& tag, double wavenumber_rad_m,
                                     const std::function<double(double)>& end_weight = {});

// An upper bound on |step − T| (step: 1 when the Keller point is on the edge, 0 past it) for every end_weight that
// takes these values at z = 0 and z = length_m (the end terms read it there alone), from the two ends: the Fresnel
// tails and the end terms bounded by parts (the .cpp has the derivation). It grows with both weights, so the ends'
// largest pattern weight bounds it for every weight. +∞ when an end is within 10⁻³ of the Keller point in τ.
// find_edge_end skips an edge's integral when even this bound cannot make its estimate reported.
double edge_truncation_deficit_bound(const Vec3& start, const Vec3& direction, double length_m, const Vec3& antenna,
                                     const Vec3& tag, double wavenumber_rad_m, double weight_at_start,
                                     double weight_at_end);

}  // namespace rfidray
