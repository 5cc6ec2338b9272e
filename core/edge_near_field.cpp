#include "core/edge_near_field.h"

#include <algorithm>
#include <cmath>

#include "core/units.h"
#include "core/wedge_series.h"

namespace rfidray {
namespace {

// 0 at x ≤ a, 1 at x ≥ b, C¹ in between (3t² − 2t³).
double smooth_step(double x, double a, double b) {
  const double t = std::clamp((x - a) / (b - a), 0.0, 1.0);
  return t * t * (3.0 - 2.0 * t);
}

}  // namespace

EdgeNearField edge_near_field(double n, double rho_m, double phi_rad, double phi_prime_rad, double k) {
  n = std::clamp(n, 1.0, 2.0);
  const double phi = std::clamp(phi_rad, 0.0, n * kPi), phi_prime = std::clamp(phi_prime_rad, 0.0, n * kPi);
  const double rho = std::clamp(rho_m, 0.0, kEdgeNearFieldMaxKrho / k);
  const WedgeField exact = wedge_plane_wave_exact(n, rho, phi, phi_prime, k);
  const WedgeField rays = wedge_plane_wave_utd(n, rho, phi, phi_prime, k);
  return {exact.soft - rays.soft, exact.hard_e_rho - rays.hard_e_rho, exact.hard_e_phi - rays.hard_e_phi};
}

double edge_near_field_weight(double krho, double far_to_near_ratio, double sin_beta0) {
  return (1.0 - smooth_step(krho, 6.0, kEdgeNearFieldMaxKrho)) * smooth_step(far_to_near_ratio, 3.0, 6.0) *
         smooth_step(sin_beta0, 0.9, 0.97);
}

}  // namespace rfidray
