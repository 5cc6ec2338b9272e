#pragma once
// The logarithmic capacity (conformal radius) of a plane conductor's cross-section: the radius of the circle with
// the same far potential per unit charge, φ(r) → −(Q/2πε) ln(r / cap). It is the radius of the circular
// cylinder that scatters like a thin conductor of that cross-section when the field is along its axis (the
// n = 0 term, which dominates for a sub-wavelength post, depends on nothing else: Van Bladel, *Electromagnetic
// Fields*, §14.5; raytrace/thin_posts.h). Closed forms: a circle of radius a, a; a segment of length w, w/4; a
// square of side s, Γ(1/4)² s / (4π^{3/2}) = 0.5902 s (Pólya & Szegő, *Isoperimetric Inequalities in
// Mathematical Physics*, 1951, Table).
//
// Computed by collocation: the boundary cut into panels graded towards the corners (where the charge is singular),
// a constant charge on each, the potential of each panel in closed form, φ = 1 at every panel's midpoint solved by
// LU (Eigen); cap = e^{−1/Q} after scaling the shape to unit size. Within 4e-5 of the closed forms above with the
// default 160 panels (2e-5 for the square; 1e-6 with 480; tests/core/test_logarithmic_capacity.cpp); ~3 ms.
// Pure function: thread-safe. Throws InputError for fewer than 2 distinct vertices or non-finite ones.
#include <span>

#include <Eigen/Core>

namespace rfidray {

// `outline`: the vertices of a convex polygon in order (closed implicitly), or 2 vertices for a segment (a sheet's
// cross-section), metres. `panels`: how many panels in all.
double logarithmic_capacity_m(std::span<const Eigen::Vector2d> outline, int panels = 160);

}  // namespace rfidray
