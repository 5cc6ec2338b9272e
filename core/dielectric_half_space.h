#pragma once
// The kernel a dielectric half-space adds to a thin wire parallel to its surface (core/thin_wire_dipole.h):
// a tag antenna on a box of water, on cardboard, on a wall.
//
// Method. The reflected parts of the mixed-potential kernels of a horizontal current above a half-space,
// as Sommerfeld integrals (Michalski & Zheng, IEEE Trans. Antennas Propag. 38(3), 1990, formulation C; the
// tangential field of a horizontal wire needs only G_A^xx and K_φ):
//     g_A(ρ) = (1/4π) ∫₀^∞ R_TE J₀(k_ρ ρ) e^{−jk_z h} k_ρ/(jk_z) dk_ρ
//     g_φ(ρ) = (1/4π) ∫₀^∞ R_φ  J₀(k_ρ ρ) e^{−jk_z h} k_ρ/(jk_z) dk_ρ,   R_φ = R_TE + (k_z²/k_ρ²)(R_TE + R_TM)
// with h = 2d (the image's depth), k_z = √(k₀² − k_ρ²), R_TE = (k_z − k_z1)/(k_z + k_z1),
// R_TM = (ε k_z − k_z1)/(ε k_z + k_z1), k_z1 = √(ε k₀² − k_ρ²) (Im ≤ 0 on both). Checks: a perfect conductor
// (R_TE = −1, R_TM = 1) gives g_A = g_φ = −e^{−jkR'}/(4πR'), the image; for large k_ρ, R_φ → −(ε − 1)/(ε + 1),
// the quasi-static image charge, which is subtracted and added back in closed form. The integrals are taken
// on the real axis, [0, k₀] with k_ρ = k₀ sin θ and [k₀, ∞) with k_ρ = √(k₀² + s²) (both remove the 1/k_z
// branch point), Gauss–Legendre panels of at most one J₀ period and a panel edge at the lower medium's branch
// point; tabulated on a grid in ρ graded with ρ + h and interpolated.
//
// Accuracy: the integrals to ~1e−6 of the image's size (tests/core/test_dielectric_half_space.cpp checks the
// conductor limit against the image in closed form); the dipole's impedance against NEC-2's Sommerfeld ground
// (GN 2) in tests/core/test_tag_antenna.cpp. The medium is an infinite half-space: a box larger than the antenna
// and deeper than the field's reach into it (in water ~λ/(2π√ε) ≈ 6 mm at 866 MHz); a thin wall (cardboard a
// few mm thick) detunes less than the half-space of its material, so there the result is an upper bound.
//
// Units: metres, hertz; ε relative and complex (ε' − jσ/(ωε₀), time dependence e^{jωt}). Thread-safe: the
// kernel is immutable after construction. Throws InputError for a non-positive distance, frequency or range,
// or Re ε < 1, Im ε > 0.
#include <complex>
#include <memory>

#include "core/thin_wire_dipole.h"

namespace rfidray {

// The half-space of relative permittivity `relative_permittivity` whose surface lies `distance_m` from the wire's
// axis; `max_separation_m` the largest |z − z'| the kernel will be asked for (the wire's length).
std::unique_ptr<WireSurroundKernel> dielectric_half_space(double distance_m, double frequency_hz,
                                                          std::complex<double> relative_permittivity,
                                                          double max_separation_m);

// The two reflected kernels at horizontal distance `rho_m` (normalised as e^{−jkR}/(4πR)), by direct quadrature:
// what the table interpolates (for tests).
struct HalfSpaceKernelValue {
  std::complex<double> vector, scalar;
};
HalfSpaceKernelValue half_space_reflected_kernel(double rho_m, double distance_m, double frequency_hz,
                                                 std::complex<double> relative_permittivity);

}  // namespace rfidray
