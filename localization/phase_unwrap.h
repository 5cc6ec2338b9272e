#pragma once
// Phase unwrapping of one (tag, antenna, channel) history, with undersampling detection.
//
// Model (paper eq. 4 / 9): φ_k = (φ0 + 4π D_k / λ + n) mod 2π. Between consecutive reads the true phase
// change is 4π ΔD / λ and |ΔD| ≤ |ΔP| (triangle inequality, ΔP = antenna displacement). Unwrapping with
// jump tolerance π picks the cycle that makes |Δφ| < π, which is right iff |ΔD| < λ/4. So a step is
// *ambiguous* — and the history is split there instead of silently adding a possibly wrong cycle — when
//   (a) step:  the antenna moved more than λ/4 between the reads (|ΔD| may reach λ/4: the cycle is unknown);
//   (b) gap:   more than `max_gap_s` passed between the reads (motion during the gap is unobserved);
//   (c) jump:  the wrapped phase change implies a range change larger than the antenna displacement allows,
//              |Δφ| λ/(4π) > |ΔP| + margin — physically impossible, so the phase jumped (outlier, multipath
//              fade, |Δφ| near π from noise) and the cycle count across it cannot be trusted.
// Each segment keeps its own unknown offset; methods treat segments as independent relative histories.
#include <span>
#include <vector>

#include "localization/observations.h"

namespace rfidray::loc {

struct UnwrapOptions {
  double frequency_hz = 865.7e6;
  double max_step_fraction = 0.25;   // (a): split when |ΔP| > fraction·λ (λ/4: the Shannon bound of §III-D)
  double max_gap_s = 1.0;            // (b)
  double jump_margin_rad = 0.6;      // (c): allowance for phase noise (≈ 6σ at the paper's 0.1 rad)
};

enum class SplitCause { kStep, kGap, kJump };

struct UnwrapSegment {
  std::vector<int> index;              // indices into the input history
  std::vector<double> unwrapped_rad;   // continuous phase, same length
};

struct UnwrapResult {
  std::vector<UnwrapSegment> segments;
  int splits_step = 0, splits_gap = 0, splits_jump = 0;
  int splits() const { return splits_step + splits_gap + splits_jump; }
};

// Classic 1-D unwrapping (jump tolerance π), no split detection: for tests and plain sequences.
std::vector<double> unwrap(std::span<const double> phase_rad);

// Unwraps one time-ordered history, splitting at ambiguous steps (see above).
UnwrapResult unwrap_history(std::span<const PhaseRead> reads, const UnwrapOptions& options);

}  // namespace rfidray::loc
