#include "localization/phase_unwrap.h"

#include <cmath>

#include "core/units.h"

namespace rfidray::loc {

std::vector<double> unwrap(std::span<const double> phase_rad) {
  std::vector<double> out(phase_rad.size());
  if (phase_rad.empty()) return out;
  out[0] = phase_rad[0];
  for (size_t k = 1; k < phase_rad.size(); ++k)
    out[k] = out[k - 1] + wrap_to_pi(phase_rad[k] - phase_rad[k - 1]);
  return out;
}

UnwrapResult unwrap_history(std::span<const PhaseRead> reads, const UnwrapOptions& options) {
  UnwrapResult result;
  if (reads.empty()) return result;
  const double lambda = wavelength_m(options.frequency_hz);
  const double max_step_m = options.max_step_fraction * lambda;
  const double rad_per_m = 4.0 * kPi / lambda;

  UnwrapSegment current;
  current.index.push_back(0);
  current.unwrapped_rad.push_back(reads[0].phase_rad);
  for (size_t k = 1; k < reads.size(); ++k) {
    const double step_m = (reads[k].antenna_m - reads[k - 1].antenna_m).norm();
    const double dt_s = reads[k].time_s - reads[k - 1].time_s;
    const double dphi = wrap_to_pi(reads[k].phase_rad - reads[k - 1].phase_rad);
    bool split = true;
    if (step_m > max_step_m) {
      ++result.splits_step;
    } else if (dt_s > options.max_gap_s) {
      ++result.splits_gap;
    } else if (std::abs(dphi) > rad_per_m * step_m + options.jump_margin_rad) {
      ++result.splits_jump;
    } else {
      split = false;
    }
    if (split) {
      result.segments.push_back(std::move(current));
      current = UnwrapSegment{};
      current.index.push_back(static_cast<int>(k));
      current.unwrapped_rad.push_back(reads[k].phase_rad);
      continue;
    }
    current.index.push_back(static_cast<int>(k));
    current.unwrapped_rad.push_back(current.unwrapped_rad.back() + dphi);
  }
  result.segments.push_back(std::move(current));
  return result;
}

}  // namespace rfidray::loc
