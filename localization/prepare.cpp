#include "localization/prepare.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "localization/mirror.h"
#include "core/units.h"

namespace rfidray::loc {

double extent_m(const std::vector<Vec3>& points) {
  if (points.size() < 2) return 0.0;
  auto farthest = [&](const Vec3& from) {
    size_t best = 0;
    double d = -1.0;
    for (size_t i = 0; i < points.size(); ++i) {
      const double di = (points[i] - from).squaredNorm();
      if (di > d) d = di, best = i;
    }
    return best;
  };
  const size_t a = farthest(points[0]);
  const size_t b = farthest(points[a]);
  return (points[a] - points[b]).norm();
}

double aperture_angle_deg(const std::vector<Vec3>& points, const Vec3& x) {
  if (points.size() < 2) return 0.0;
  std::vector<Vec3> dirs;
  dirs.reserve(points.size());
  for (const Vec3& p : points) {
    const Vec3 d = p - x;
    const double n = d.norm();
    if (n > 0.0) dirs.push_back(d / n);
  }
  if (dirs.size() < 2) return 0.0;
  auto widest = [&](const Vec3& from) {
    size_t best = 0;
    double c = 2.0;
    for (size_t i = 0; i < dirs.size(); ++i) {
      const double ci = dirs[i].dot(from);
      if (ci < c) c = ci, best = i;
    }
    return best;
  };
  const size_t a = widest(dirs[0]);
  const size_t b = widest(dirs[a]);
  return std::acos(std::clamp(dirs[a].dot(dirs[b]), -1.0, 1.0)) * 180.0 / kPi;
}

std::optional<LocalizeResult> prepare(const TagReads& tag, const LocalizeOptions& options, PreparedTag& out) {
  out = PreparedTag{};
  std::vector<Vec3> all_positions;
  std::vector<double> steps;
  for (size_t g = 0; g < tag.groups.size(); ++g) {
    const ReadGroup& group = tag.groups[g];
    for (size_t k = 0; k < group.reads.size(); ++k) {
      all_positions.push_back(group.reads[k].antenna_m);
      if (k > 0) steps.push_back((group.reads[k].antenna_m - group.reads[k - 1].antenna_m).norm());
    }
    UnwrapOptions uo = options.unwrap;
    uo.frequency_hz = group.frequency_hz;
    const UnwrapResult u = unwrap_history(group.reads, uo);
    out.splits_step += u.splits_step;
    out.splits_gap += u.splits_gap;
    out.splits_jump += u.splits_jump;
    const double lambda = wavelength_m(group.frequency_hz);
    for (const UnwrapSegment& s : u.segments) {
      if (static_cast<int>(s.index.size()) < options.min_segment_reads) continue;
      // A (nearly) stationary antenna sees a constant range: with the offset unknown it carries no position
      // information (a fixed antenna), and its position would only distort the path's line/plane fit.
      std::vector<Vec3> seg_positions;
      for (int i : s.index) seg_positions.push_back(group.reads[i].antenna_m);
      if (extent_m(seg_positions) < options.min_segment_extent_m) continue;
      RangeSegment rs;
      rs.group = static_cast<int>(g);
      rs.wavelength_m = lambda;
      for (size_t i = 0; i < s.index.size(); ++i) {
        const PhaseRead& r = group.reads[s.index[i]];
        rs.antenna_m.push_back(r.antenna_m);
        rs.range_m.push_back(s.unwrapped_rad[i] * lambda / (4.0 * kPi));
        out.positions.push_back(r.antenna_m);
        out.orientations.push_back(r.antenna_orientation);
      }
      out.usable_reads += static_cast<int>(s.index.size());
      out.segments.push_back(std::move(rs));
    }
  }
  out.total_reads = static_cast<int>(all_positions.size());
  out.path_aperture_m = extent_m(all_positions);
  out.usable_aperture_m = extent_m(out.positions);
  if (!steps.empty()) {
    std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
    out.median_step_m = steps[steps.size() / 2];
  }

  std::ostringstream why;
  if (out.total_reads < options.min_reads) {
    why << out.total_reads << " reads, need " << options.min_reads;
    return LocalizeResult::failure(FailReason::kTooFewReads, why.str());
  }
  if (out.path_aperture_m < options.min_aperture_m) {
    why << "antenna path extent " << out.path_aperture_m << " m < " << options.min_aperture_m << " m";
    return LocalizeResult::failure(FailReason::kApertureTooShort, why.str());
  }
  if (out.usable_reads < options.min_reads || out.usable_aperture_m < options.min_aperture_m) {
    why << "after splitting at ambiguous steps (" << out.splits_step << " moves > λ/4, " << out.splits_gap
        << " gaps, " << out.splits_jump << " phase jumps) only " << out.usable_reads << " reads spanning "
        << out.usable_aperture_m << " m remain usable";
    if (out.splits_step + out.splits_jump > 0)
      return LocalizeResult::failure(FailReason::kUndersampled, why.str());
    return LocalizeResult::failure(out.usable_reads < options.min_reads ? FailReason::kTooFewReads
                                                                         : FailReason::kApertureTooShort,
                                   why.str());
  }

  Vec3 unused;
  if (!options.height_known && !reflect_across_path(out.positions, false, out.positions[0], unused))
    return LocalizeResult::failure(FailReason::kAmbiguousMirror,
                                   "straight antenna path in 3-D: the tag can be anywhere on a circle around it");

  out.region_min = out.region_max = out.positions[0];
  for (const Vec3& p : out.positions) {
    out.region_min = out.region_min.cwiseMin(p);
    out.region_max = out.region_max.cwiseMax(p);
  }
  out.region_min.array() -= options.max_range_m;
  out.region_max.array() += options.max_range_m;
  if (options.height_known) out.region_min.z() = out.region_max.z() = options.tag_height_m;
  return std::nullopt;
}

std::optional<LocalizeResult> check_aperture_angle(const PreparedTag& prep, const Vec3& estimate,
                                                   const LocalizeOptions& options) {
  const double angle = aperture_angle_deg(prep.positions, estimate);
  if (angle >= options.min_aperture_angle_deg) return std::nullopt;
  std::ostringstream why;
  why << "antenna path seen from the estimate under " << angle << " deg < " << options.min_aperture_angle_deg
      << " deg";
  LocalizeResult r = LocalizeResult::failure(FailReason::kApertureTooShort, why.str());
  r.position = estimate;
  return r;
}

}  // namespace rfidray::loc
