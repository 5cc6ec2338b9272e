#pragma once
// The conics of the paper's method (§III-D, Fig. 7–8). Two antenna positions F1 (reference AP0) and F2
// (current AP1) and the unwrapped range change Δr define the locus |x − F2| − |x − F1| = Δr: one sheet of a
// hyperboloid of revolution with foci F1, F2. Its section with a horizontal plane z = h (known tag height)
// is a conic — the paper's hyperbola when F1, F2 lie in a plane parallel to it.
//
// Plane sections are computed in polar form around F1: on the ray x = F1_xy + ρ(cos ψ, sin ψ), z = h, the
// locus condition squared twice is a quadratic in ρ,
//   4((e·δ)² − Δ²) ρ² − 4K(e·δ) ρ + K² − 4Δ²c1² = 0,  K = |δ|² + c2² − c1² − Δ²,
// (δ = F2_xy − F1_xy, c_i = h − F_i.z), and a root belongs to the right sheet iff Δ·(K − 2ρ e·δ) ≥ 0.
#include <Eigen/Core>
#include <vector>

#include "core/geometry.h"

namespace rfidray::loc {

struct Hyperbola {
  Vec3 f1 = Vec3::Zero(), f2 = Vec3::Zero();
  double delta_m = 0.0;              // Δr = |x − F2| − |x − F1|
  double phase_distance_m = 0.0;     // unwrapped phase distance at F2 (phiDist_n of the paper)
  bool valid() const { return std::abs(delta_m) < (f2 - f1).norm(); }
};

// Signed locus residual |x − F2| − |x − F1| − Δr (m); its gradient (u2 − u1) has norm 2 sin(α/2), α the
// angle F1–x–F2.
double residual(const Hyperbola& h, const Vec3& x);
Vec3 gradient(const Hyperbola& h, const Vec3& x);

// Points of the plane section, ray by ray: up to two per ray ψ (slot 0/1 = −/+ root of the quadratic).
bool point_on_ray(const Hyperbola& h, double height_m, double psi_rad, int slot, Vec3& out);

// The section sampled on `rays` equally spaced rays, points beyond max_range_m of F2 marked invalid.
// The valid samples are also kept packed, slot by slot in ray order (x, y and their distance to the conic's
// F1), so that another conic's residual is evaluated only where the section exists (often under half of the
// 2 × rays samples) and its sign changes are found in one pass over consecutive entries.
struct PlaneSection {
  int rays = 0;
  double height_m = 0.0;
  Vec3 f1 = Vec3::Zero();    // the sampled conic's F1
  std::vector<Vec3> points;  // rays × 2, row-major [ray][slot]
  std::vector<int> packed;   // per sample: its index in x_m/y_m/r1_m, −1 where invalid
  std::vector<int> sample_of;       // per packed entry: its sample index (2 · ray + slot)
  std::vector<char> next_is_ray_after;  // per packed entry: the next entry is the same slot on the next ray
  std::vector<double> x_m, y_m;  // the valid points' x and y, packed
  std::vector<double> r1_m;       // the valid points' distance to f1, packed
  // Per packed entry k: Σ_{i<k} |p_{i+1} − p_i| over the packed order (a bound on |p_j − p_k| for j > k,
  // by the triangle inequality): intersect_in_plane skips blocks of samples it proves free of sign changes.
  std::vector<double> chord_sum_m;
  double scale_m = 0.0;  // the largest |coordinate| of a valid point (for the rounding margin)
  bool valid(int sample) const { return packed[sample] >= 0; }
};
PlaneSection sample_section(const Hyperbola& h, double height_m, int rays, double max_range_m);
// The same into `out`, reusing its storage (the method samples ~60 sections per tag).
void sample_section(const Hyperbola& h, double height_m, int rays, double max_range_m, PlaneSection& out);

// All intersections of two plane sections (sign changes of h2's residual along h1's section, refined by
// regula falsi (Illinois) on the ray angle and polished by Newton on both loci). Exact to ~1e-9 m.
std::vector<Vec3> intersect_in_plane(const Hyperbola& h1, const PlaneSection& s1, const Hyperbola& h2);
// The same into `out` (cleared first; its storage reused across calls).
void intersect_in_plane(const Hyperbola& h1, const PlaneSection& s1, const Hyperbola& h2, std::vector<Vec3>& out);
// The same with the block sizes of its sign-change search given (coarse ≥ fine ≥ 1; 1, 1 evaluates every
// sample): the points are bitwise the same for any sizes, which the tests check.
void intersect_in_plane(const Hyperbola& h1, const PlaneSection& s1, const Hyperbola& h2, std::vector<Vec3>& out,
                        int coarse_block, int fine_block);

// Intersection of three hyperboloids (3-D) by Gauss–Newton from `seed`; false if it does not converge.
bool intersect_3d(const Hyperbola& a, const Hyperbola& b, const Hyperbola& c, const Vec3& seed, Vec3& out);

// Quality of an intersection: 1 / GDOP = 1 / sqrt(trace((JᵀJ)⁻¹)), J = the loci gradients (rows) in the
// unknown coordinates (xy in 2-D). A range error σ moves the point by about σ·GDOP, so larger is better.
// `count` ≤ 3 gradients (no allocation: called for every intersection).
double intersection_quality(const Vec3* gradients, int count, bool planar);
inline double intersection_quality(const std::vector<Vec3>& gradients, bool planar) {
  return intersection_quality(gradients.data(), static_cast<int>(gradients.size()), planar);
}

}  // namespace rfidray::loc
