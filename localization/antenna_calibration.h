#pragma once
// What a calibration from reference tags knows about one antenna (plain values; fitted by calibration.h,
// stored by io/antenna_file.h, applied by the joint phase model when LocalizeOptions::calibration is set).
//
// Model of a read of a tag at T by this antenna at position P with orientation q (boresight = local +X) on
// carrier f (k = 4πf/c):
//   φ = ν_tag + c_f + k |T − P'| + pattern(az, el)  (mod 2π),   P' = P + q·phase_centre_offset_m,
// where (az, el) is the direction of T seen from P' in the antenna frame (az = atan2(y, x), el = atan2(z,
// hypot(x, y)), radians), pattern = Σ_t coefficient_t · basis_t(az, el) over kPatternTerms (no constant:
// a constant is one more per-tag offset ν), c_f the reader chain's offset of carrier f relative to the first
// carrier (c_{f0} = 0). Standard uncertainties (sd) are 1-σ from the calibration fit; `geometry_covariance`
// is the fit's covariance of the 3 + 5 parameters that bend a tag's phase along the aperture (the phase-centre
// offset and the pattern: strongly correlated, both curve the wavefront), which localization propagates into
// each tag's uncertainty (joint_fit.h).
#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "core/geometry.h"

namespace rfidray::loc {

// Pattern basis: az, el, az², az·el, el² (radians). Low order on purpose: a UHF patch's phase varies
// smoothly over its beam.
inline constexpr int kPatternTerms = 5;
inline constexpr double kHalfPiRad = 1.57079632679489661923;
// The pattern is calibrated from tags in front of the antenna; behind it (|az| > π/2) it is held at its value
// at the side (az = ±π/2) instead of extrapolating the polynomial, which would otherwise let a fit behind the
// antenna bend the phase freely.
inline std::array<double, kPatternTerms> pattern_basis(double az_rad, double el_rad) {
  const double az = std::clamp(az_rad, -kHalfPiRad, kHalfPiRad);
  return {az, el_rad, az * az, az * el_rad, el_rad * el_rad};
}
inline const char* const kPatternTermNames[kPatternTerms] = {"az", "el", "az2", "az_el", "el2"};
// The parameters of geometry_covariance: phase-centre offset x, y, z (m, antenna frame), then the pattern terms.
inline constexpr int kGeometryTerms = 3 + kPatternTerms;
inline const char* const kGeometryTermNames[kGeometryTerms] = {"dx", "dy", "dz", "az", "el", "az2", "az_el", "el2"};
using GeometryCovariance = Eigen::Matrix<double, kGeometryTerms, kGeometryTerms>;

struct AntennaCalibration {
  std::string antenna;                        // antenna name as in the readings' `antenna` column
  Vec3 phase_centre_offset_m = Vec3::Zero();  // antenna frame
  Vec3 phase_centre_offset_sd_m = Vec3::Zero();
  std::vector<double> frequencies_hz;         // calibrated carriers, ascending; first has offset 0
  std::vector<double> carrier_offsets_rad;    // c_f, same order
  std::vector<double> carrier_offsets_sd_rad;
  std::array<double, kPatternTerms> pattern_rad{};     // coefficients of pattern_basis
  std::array<double, kPatternTerms> pattern_sd_rad{};
  // Covariance of (offset, pattern) in m², m·rad, rad²; all zero when unknown (files written before it:
  // geometry_covariance_or_sd() then takes the sd's as uncorrelated).
  GeometryCovariance geometry_covariance = GeometryCovariance::Zero();
  // Terms of the geometry (kGeometryTermNames) the reference tags could not determine, held at 0 (sd 0), each
  // with the reason (e.g. dz from reference tags and antenna stops in one plane: the range depends on it only
  // to second order and not on its sign); and terms fitted but bounded by the prior (their sd is nearly the
  // prior's: the data hardly move them).
  struct TermNote {
    std::string term;
    std::string why;
  };
  std::vector<TermNote> not_fitted;
  std::vector<TermNote> prior_bounded;
  // Pairs of fitted geometry terms whose estimates are correlated beyond ±0.98 (term "dx/az2"): the references
  // tell only a combination of the two (e.g. a phase centre along boresight and the az² curvature, which both
  // curve the wavefront). Not written to the antenna file (its geometry_covariance holds the correlation).
  std::vector<TermNote> aliased;
  // Why no carrier offsets were calibrated when calibrate kept nothing (CalibrationOptions::fit_carriers, chosen by
  // the held-out check: frequencies_hz is then empty and each carrier keeps its own offset); empty otherwise.
  std::string carriers_not_fitted;
  // The radius allowance measured on the reference tags (calibration.h): σ_sys = max(allowance_base_rad,
  // allowance_smooth_factor × a fit's smooth misfit) is the smallest pair (in median radius) whose 95 % radius
  // covers ≥ 95 % of the reference tags, each localized with this calibration. NaN: not measured.
  double allowance_base_rad = std::numeric_limits<double>::quiet_NaN();
  double allowance_smooth_factor = std::numeric_limits<double>::quiet_NaN();
  int allowance_samples = 0;          // reference tags it was measured on
  double allowance_coverage = std::numeric_limits<double>::quiet_NaN();  // their share inside the radius
  bool has_allowance() const { return std::isfinite(allowance_base_rad) && std::isfinite(allowance_smooth_factor); }
  // The same allowance measured apart on the reference tags of each band of tag spacing (a tag's distance to its
  // nearest reference neighbour in its run; a tag alone in its run: infinite), bands split at half the wavelength
  // of the lowest carrier the references were read on: in a denser row each tag's phase also carries its neighbours' coupling, which the
  // fit cannot see (on the AdaRF training runs, 95 % of tags 20 cm apart need σ_sys ≤ 0.09 rad, of tags 4–10 cm
  // apart ≤ 0.34 rad). A band with fewer than 10 localized reference tags is not listed. localize uses the
  // band of the spacing the user gives (LocalizeRequest::tag_spacing_m), else the pooled allowance above.
  struct AllowanceBand {
    double spacing_from_m = 0.0;                                          // inclusive
    double spacing_below_m = std::numeric_limits<double>::infinity();     // exclusive; infinity: no upper end
    double base_rad = 0.0;
    double smooth_factor = 0.0;
    int samples = 0;
    double coverage = std::numeric_limits<double>::quiet_NaN();
    bool contains(double spacing_m) const { return spacing_m >= spacing_from_m && spacing_m < spacing_below_m; }
  };
  std::vector<AllowanceBand> allowance_bands;  // ascending spacing, disjoint
  // The band holding `spacing_m`; nullptr when none does (or spacing_m is NaN).
  const AllowanceBand* allowance_band_for(double spacing_m) const {
    for (const AllowanceBand& b : allowance_bands)
      if (b.contains(spacing_m)) return &b;
    return nullptr;
  }
  // Whether the calibration helps where it was made: the antenna's own reference tags (fit_geometry samples)
  // localized as the allowance localizes them, with this calibration and without any; medians over the tags
  // localized both ways. NaN: not measured. Not written to the antenna file (calibrate prints it and warns
  // when the first is not below the second: held-out tags then seldom fare better).
  double reference_median_error_m = std::numeric_limits<double>::quiet_NaN();
  double reference_median_error_uncalibrated_m = std::numeric_limits<double>::quiet_NaN();
  int reference_error_tags = 0;
  bool helps_its_references() const {
    return !(reference_median_error_m >= reference_median_error_uncalibrated_m);  // true when not measured
  }
  // Whether it helps tags it was not fitted on: the runs of references dealt to folds, each fold's tags localized
  // with the calibration fitted on the other folds' runs and without any (allowance.h, measure_held_out); medians
  // over the tags localized both ways. NaN: not measured (fewer than 2 runs). Not written to the antenna file.
  double held_out_median_error_m = std::numeric_limits<double>::quiet_NaN();
  double held_out_median_error_uncalibrated_m = std::numeric_limits<double>::quiet_NaN();
  int held_out_tags = 0;
  int held_out_runs = 0;   // runs of reference tags dealt to the folds
  int held_out_folds = 0;  // folds whose calibration could be fitted
  bool helps_held_out() const {
    return !(held_out_median_error_m >= held_out_median_error_uncalibrated_m);  // true when not measured
  }
  // The models calibrate tried when it chose its terms by the held-out check (CalibrationOptions::select_terms),
  // richest first; empty when it did not choose. Not written to the antenna file.
  struct HeldOutModel {
    std::string terms;               // e.g. "carrier offsets + phase-centre offset + pattern"
    double median_error_m = 0.0;     // held-out median error with it (NaN: not measured)
    bool kept = false;
  };
  std::vector<HeldOutModel> held_out_models;
  double residual_rms_rad = 0.0;  // RMS wrapped residual of the fit (per stop mean)
  int reads_used = 0;
  int tags_used = 0;              // tag × run pairs (each with its own nuisance offset)

  bool has_carrier_offsets() const { return frequencies_hz.size() >= 2; }
  // Index of the calibrated carrier within 1 kHz of f, or −1.
  int carrier_index(double frequency_hz) const {
    for (size_t i = 0; i < frequencies_hz.size(); ++i)
      if (std::abs(frequencies_hz[i] - frequency_hz) < 1e3) return static_cast<int>(i);
    return -1;
  }
  // World position of the phase centre for an antenna reference pose.
  Vec3 phase_centre(const Vec3& antenna_m, const Quat& orientation) const {
    return antenna_m + orientation * phase_centre_offset_m;
  }
  GeometryCovariance geometry_covariance_or_sd() const {
    if (!geometry_covariance.isZero(0.0)) return geometry_covariance;
    GeometryCovariance c = GeometryCovariance::Zero();
    for (int a = 0; a < 3; ++a) c(a, a) = phase_centre_offset_sd_m[a] * phase_centre_offset_sd_m[a];
    for (int t = 0; t < kPatternTerms; ++t) c(3 + t, 3 + t) = pattern_sd_rad[t] * pattern_sd_rad[t];
    return c;
  }
  double pattern_phase_rad(double az_rad, double el_rad) const {
    const auto b = pattern_basis(az_rad, el_rad);
    double s = 0.0;
    for (int t = 0; t < kPatternTerms; ++t) s += pattern_rad[t] * b[t];
    return s;
  }
};

// Direction (az, el) of `target` seen from `centre` in the frame of `orientation`.
inline void direction_in_frame(const Vec3& centre, const Quat& orientation, const Vec3& target, double& az_rad,
                               double& el_rad) {
  const Vec3 d = orientation.conjugate() * (target - centre);
  az_rad = std::atan2(d.y(), d.x());
  el_rad = std::atan2(d.z(), std::hypot(d.x(), d.y()));
}

}  // namespace rfidray::loc
