#pragma once
// One propagation path of an antenna–tag link and the complex channel they sum to.
// h = Σ_i (λ / 4π L_i) · g_R,i · g_T,i · Γ_i · e^{-j k L_i}   (one way; round trip is h², paper eq. 1)
#include <complex>
#include <string>
#include <vector>

#include "core/geometry.h"
#include "core/units.h"

namespace rfidray {

// kEdgeNearField: level full's near field of an edge at an end a few centimetres from it (core/edge_near_field.h),
// listed beside the edge's diffracted ray with the same point and length.
// kPostScattering: the field scattered by a thin metal post (levels full-selective and full: raytrace/thin_posts.h).
// kDiffraction2: diffracted at two parallel edges in turn (levels full-selective and full:
// raytrace/double_diffraction.cpp), e.g. along a shelf plate from its front edge to its back edge.
enum class PathKind {
  kLineOfSight, kBlocked, kReflection, kReflection2, kDiffraction, kEdgeNearField, kPostScattering, kDiffraction2
};

inline const char* to_string(PathKind k) {
  switch (k) {
    case PathKind::kLineOfSight: return "los";
    case PathKind::kBlocked: return "blocked";
    case PathKind::kReflection: return "reflection";
    case PathKind::kReflection2: return "reflection2";
    case PathKind::kDiffraction: return "diffraction";
    case PathKind::kEdgeNearField: return "edge-near-field";
    case PathKind::kPostScattering: return "post";
    case PathKind::kDiffraction2: return "diffraction2";
  }
  return "?";
}

struct Path {
  PathKind kind = PathKind::kLineOfSight;
  double length_m = 0.0;
  // Interaction point: the reflection point for reflections (the first one for reflection2), the diffraction
  // point on the edge for diffraction (on the first edge for diffraction2); for blocked paths the first crossing.
  Vec3 point = Vec3::Zero();
  std::string material;  // material of the reflecting / crossed surface, or of the wedge's face 0 ("" for LoS)
  // reflection2: the second reflection point and its surface's material; diffraction2: the second edge's
  // diffraction point and its face 0's material.
  Vec3 point2 = Vec3::Zero();
  std::string material2;
  int crossings = 0;     // surfaces crossed (blocked paths)
  // Everything but spreading and propagation phase: √(G_R G_T) in the path directions,
  // polarization match, Fresnel / transmission coefficients.
  std::complex<double> coefficient{1.0, 0.0};
  // The path's contribution to the one-way channel h.
  std::complex<double> contribution{0.0, 0.0};
};

// Contribution of one path: (λ / 4π L) · coefficient · e^{-j k L}.
inline std::complex<double> path_contribution(double length_m, std::complex<double> coefficient,
                                              double frequency_hz) {
  const double lambda = wavelength_m(frequency_hz);
  return coefficient * (lambda / (4.0 * kPi * length_m)) *
         std::polar(1.0, -wavenumber_rad_m(frequency_hz) * length_m);
}

inline std::complex<double> sum_paths(const std::vector<Path>& paths) {
  std::complex<double> h{0.0, 0.0};
  for (const Path& p : paths) h += p.contribution;
  return h;
}

}  // namespace rfidray
