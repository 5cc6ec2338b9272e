#pragma once
// The phase error that a known scene adds at a tag position: the bias allowance of `localize --scenario`.
//
// A localizer models the direct path only. Where the scene is known (a simulated warehouse, a surveyed site)
// the caller evaluates, for a tag position x and the tag's antenna positions k, the one-way channel with every
// path the scene has, h_k(x), and the free-space direct path alone, h0_k(x). The backscatter phase then carries
// the error ε_k = 2·arg(h_k / h0_k) (down and back through the same channel). Its mean over the aperture is a
// constant that the carrier offsets absorb; what is left changes smoothly along the aperture, a fit absorbs it
// by moving the position, and the residuals cannot show it — a wall 0.1 m behind a tag moves a 1 m-aperture fit
// by ~7 cm with residuals at the noise level. So it is not corrected but bounded: its RMS about the circular
// mean is an allowance σ_sys of the bias bound in joint_fit.h (σ_sys·sqrt(N λ_max((J_uᵀJ_u)⁻¹)), Cauchy–Schwarz).
//
// Pure functions, thread-safe, no allocation beyond the result; never throw.
#include <complex>
#include <span>

namespace rfidray::loc {

// RMS (rad) of ε_k = 2·arg(ratio_k) about its circular mean, ratio_k = h_k / h0_k. +inf when a ratio is zero
// or not finite (no path reaches the tag from an antenna position: the phase there is unknown), 0 when empty.
double multipath_phase_rms_rad(std::span<const std::complex<double>> ratio);

}  // namespace rfidray::loc
