// Holographic / SAR baseline: matched filter of the wrapped phases over a grid, no unwrapping.
//   S(x) = Σ_g |Σ_{k∈g} exp(j(φ_k − 4π|x − P_k|/λ_g))|² / Σ_g N_g²  ∈ [0, 1]
// Each group (antenna, channel) is summed coherently — its φ0 only rotates the sum — and groups are added
// in power, since their offsets differ. Coarse grid (λ/4, reads decimated to ≥ λ/8 spacing), then the best
// separated peaks are refined by shrinking 5×5(×5) local grids down to sar_fine_step_m.
// Failure: besides the shared checks, a second distinct peak that fits the wrapped phases as well as the
// best one (χ² test on wrapped residuals) means grating lobes: undersampled when reads are > λ/4 apart.
#include <cmath>
#include <complex>
#include <limits>
#include <sstream>

#include "localization/finish.h"
#include "localization/grid.h"
#include "localization/methods.h"
#include "localization/mirror.h"
#include "localization/prepare.h"
#include "core/units.h"

namespace rfidray::loc {

namespace {

struct SarRead {
  Vec3 p;
  double phase_rad;
  double k_rad_m;  // 4π/λ
};

class SarFocus {
 public:
  SarFocus(const TagReads& tag, double decimate_m) {
    for (const ReadGroup& g : tag.groups) {
      const double k = 4.0 * kPi / wavelength_m(g.frequency_hz);
      std::vector<SarRead> reads;
      Vec3 last = Vec3::Constant(std::numeric_limits<double>::infinity());
      for (const PhaseRead& r : g.reads) {
        if (decimate_m > 0.0 && (r.antenna_m - last).norm() < decimate_m) continue;
        last = r.antenna_m;
        reads.push_back({r.antenna_m, r.phase_rad, k});
      }
      if (reads.empty()) continue;
      norm_ += static_cast<double>(reads.size()) * static_cast<double>(reads.size());
      count_ += static_cast<int>(reads.size());
      groups_.push_back(std::move(reads));
    }
  }
  int count() const { return count_; }

  double score(const Vec3& x) const {
    double total = 0.0;
    for (const auto& g : groups_) {
      double re = 0.0, im = 0.0;
      for (const SarRead& r : g) {
        const double a = r.phase_rad - r.k_rad_m * (x - r.p).norm();
        re += std::cos(a);
        im += std::sin(a);
      }
      total += re * re + im * im;
    }
    return norm_ > 0.0 ? total / norm_ : 0.0;
  }

  // Wrapped-phase SSR (rad²) with each group's offset at its coherent-sum angle.
  double ssr(const Vec3& x) const {
    double total = 0.0;
    for (const auto& g : groups_) {
      std::complex<double> sum = 0.0;
      for (const SarRead& r : g) sum += std::polar(1.0, r.phase_rad - r.k_rad_m * (x - r.p).norm());
      const double psi = std::arg(sum);
      for (const SarRead& r : g) {
        const double e = wrap_to_pi(r.phase_rad - r.k_rad_m * (x - r.p).norm() - psi);
        total += e * e;
      }
    }
    return total;
  }

 private:
  std::vector<std::vector<SarRead>> groups_;
  double norm_ = 0.0;
  int count_ = 0;
};

Vec3 refine_peak(const SarFocus& f, Vec3 x, double step, double fine_step, bool planar) {
  double best = f.score(x);
  while (step >= fine_step) {
    bool moved = false;
    Vec3 best_x = x;
    const int zr = planar ? 0 : 2;
    for (int dz = -zr; dz <= zr; ++dz)
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          if (dx == 0 && dy == 0 && dz == 0) continue;
          const Vec3 c = x + step * Vec3(dx, dy, dz);
          const double s = f.score(c);
          if (s > best) best = s, best_x = c, moved = true;
        }
    x = best_x;
    if (!moved) step *= 0.5;  // the optimum is inside this window: zoom in
  }
  return x;
}

}  // namespace

LocalizeResult localize_sar(const TagReads& tag, const LocalizeOptions& options) {
  // The shared pre-checks without unwrapping splits (SAR never unwraps).
  LocalizeOptions no_split = options;
  no_split.unwrap.max_step_fraction = std::numeric_limits<double>::infinity();
  no_split.unwrap.max_gap_s = std::numeric_limits<double>::infinity();
  no_split.unwrap.jump_margin_rad = std::numeric_limits<double>::infinity();
  no_split.min_segment_reads = 1;
  PreparedTag prep;
  if (auto fail = prepare(tag, no_split, prep)) return *fail;

  double lambda_min = std::numeric_limits<double>::infinity();
  for (const ReadGroup& g : tag.groups) lambda_min = std::min(lambda_min, wavelength_m(g.frequency_hz));
  const bool planar = options.height_known;
  const SarFocus coarse(tag, lambda_min / 8.0);
  const SarFocus full(tag, 0.0);

  const Grid grid = make_grid(prep.region_min, prep.region_max, options.sar_coarse_step_fraction * lambda_min,
                              planar ? 60000 : 120000);
  std::vector<double> value(grid.size());
#pragma omp parallel for schedule(static)
  for (long i = 0; i < grid.size(); ++i) value[i] = -coarse.score(grid.point(i));
  const std::vector<long> peaks = best_separated(grid, value, options.sar_peaks, lambda_min / 2.0);

  std::vector<Vec3> refined;
  for (long i : peaks) refined.push_back(refine_peak(full, grid.point(i), grid.step_m / 2.0, options.sar_fine_step_m, planar));
  LocalizeResult result;
  result.reads_used = full.count();
  result.segments = static_cast<int>(tag.groups.size());
  if (refined.empty()) return LocalizeResult::failure(FailReason::kNoConvergence, "empty search grid");
  size_t best = 0;
  for (size_t i = 1; i < refined.size(); ++i)
    if (full.score(refined[i]) > full.score(refined[best])) best = i;
  result.ok = true;
  result.position = refined[best];
  const double best_ssr = full.ssr(result.position);
  result.rms_residual_m = std::sqrt(best_ssr / std::max(1, full.count())) * lambda_min / (4.0 * kPi);
  if (auto fail = check_aperture_angle(prep, result.position, options)) {
    fail->reads_used = result.reads_used;
    return *fail;
  }

  // Uncertainty gate on the same geometry (groups as segments), σ from the wrapped-phase residual.
  {
    const RangeCost cost(prep, options.height_known, options.tag_height_m);
    const int dof = std::max(1, full.count() - (planar ? 2 : 3) - static_cast<int>(tag.groups.size()));
    gate_uncertainty(result, prep, cost, std::sqrt(best_ssr / dof) * lambda_min / (4.0 * kPi), options);
    if (!result.ok) return result;
  }

  const double floor_rad = options.noise_floor_m * 4.0 * kPi / lambda_min;
  const int dof_left = std::max(1, full.count() - (planar ? 2 : 3) - static_cast<int>(tag.groups.size()));
  const double sigma2 = std::max(best_ssr / dof_left, floor_rad * floor_rad);

  // Mirror across the path, judged by the SAR's own wrapped-phase fit.
  Objective objective;
  objective.ssr = [&](const Vec3& x) { return full.ssr(x); };
  objective.refine = [&](const Vec3& x) { return refine_peak(full, x, lambda_min / 4.0, options.sar_fine_step_m, planar); };
  objective.residuals = full.count();
  objective.region_min = prep.region_min;
  objective.region_max = prep.region_max;
  objective.dof = (planar ? 2 : 3) + static_cast<int>(tag.groups.size());
  const MirrorCheck check = check_mirror(prep.positions, result.position, objective, options, floor_rad);
  Vec3 reflected = result.position;
  reflect_across_path(prep.positions, options.height_known, result.position, reflected);

  // Grating lobes / ambiguous peaks: another distinct peak (not the mirror) that fits as well.
  for (size_t i = 0; i < refined.size(); ++i) {
    if (i == best) continue;
    if ((refined[i] - result.position).norm() < lambda_min / 2.0) continue;
    if ((refined[i] - reflected).norm() < lambda_min / 2.0 || (check.ambiguous && (refined[i] - check.mirror).norm() < lambda_min / 2.0))
      continue;
    const double dchi2 = (full.ssr(refined[i]) - best_ssr) / sigma2;
    if (dchi2 >= options.mirror_chi2) continue;
    std::ostringstream why;
    why << "second peak at (" << refined[i].x() << ", " << refined[i].y() << ", " << refined[i].z()
        << ") fits within " << dchi2 << " chi2 units";
    const bool under = prep.median_step_m > lambda_min / 4.0;
    if (under) why << "; median read spacing " << prep.median_step_m << " m > λ/4 (grating lobes)";
    LocalizeResult fail = LocalizeResult::failure(under ? FailReason::kUndersampled : FailReason::kNoConvergence, why.str());
    fail.reads_used = result.reads_used;
    return fail;
  }
  settle_mirror(result, check, prep.positions, prep.orientations, options);
  return result;
}

}  // namespace rfidray::loc
