// calibrate(): an antenna calibration from reference tags, as `rfidray calibrate` (io/reference_tags.h,
// loc::calibrate_antenna), with readings and truth passed as localize() takes them (readings_arg.h).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <optional>
#include <set>

#include "core/error.h"
#include "io/antenna_file.h"
#include "io/atomic_file.h"
#include "io/reference_tags.h"
#include "localization/calibration.h"
#include "python/bindings/bindings.h"
#include "python/bindings/readings_arg.h"

namespace rfidray::py {
namespace {

// references: a list of (files, truth) — files a list of column dicts (one per readings file), truth as
// truth_from takes it.
pyb::dict run_calibrate(const pyb::list& references, const std::string& antenna_requested, bool height_known,
                        bool fold_pi, std::optional<std::string> output) {
  std::vector<loc::CalibrationSample> samples;
  std::set<std::string> antennas;
  size_t file = 0;
  for (size_t k = 0; k < references.size(); ++k) {
    const pyb::tuple pair = references[k].cast<pyb::tuple>();
    if (pair.size() != 2) throw InputError("references[" + std::to_string(k) + "]: needs (readings, truth)");
    if (pair[1].is_none()) throw InputError("references[" + std::to_string(k) + "]: truth is None");
    const std::map<std::string, Vec3> truth = truth_from(pair[1]);
    const size_t before = samples.size();
    for (auto f : pair[0].cast<pyb::list>()) io::add_reference_tags(rows_from(f.cast<pyb::dict>(), file++), truth, samples, antennas);
    for (size_t i = before; i < samples.size(); ++i) samples[i].run = static_cast<int>(k);  // one run per reference
  }
  const std::string antenna = io::antenna_to_calibrate(antenna_requested, antennas, "antenna");
  loc::CalibrationOptions o;
  o.planar = height_known;
  o.fold_pi = fold_pi;
  loc::AntennaCalibration c;
  {
    pyb::gil_scoped_release release;
    c = loc::calibrate_antenna(samples, antenna, o);
  }
  if (output) {
    io::check_output_path(*output, "antenna file");
    io::write_file_atomic(*output, [&](std::ostream& out) { io::write_antenna_file(out, c); }, "antenna file");
  }
  // The keys of `rfidray calibrate --json` (without output).
  auto vec = [](const Vec3& v) { return pyb::array_t<double>(3, v.data()); };
  pyb::dict d;
  d["antenna"] = c.antenna;
  d["phase_centre_offset_m"] = vec(c.phase_centre_offset_m);
  d["phase_centre_offset_sd_m"] = vec(c.phase_centre_offset_sd_m);
  d["frequencies_hz"] = pyb::array_t<double>(c.frequencies_hz.size(), c.frequencies_hz.data());
  d["carrier_offsets_rad"] = pyb::array_t<double>(c.carrier_offsets_rad.size(), c.carrier_offsets_rad.data());
  d["carrier_offsets_sd_rad"] = pyb::array_t<double>(c.carrier_offsets_sd_rad.size(), c.carrier_offsets_sd_rad.data());
  d["pattern_rad"] = pyb::array_t<double>(c.pattern_rad.size(), c.pattern_rad.data());
  d["pattern_sd_rad"] = pyb::array_t<double>(c.pattern_sd_rad.size(), c.pattern_sd_rad.data());
  pyb::array_t<double> cov({loc::kGeometryTerms, loc::kGeometryTerms});
  for (int i = 0; i < loc::kGeometryTerms; ++i)
    for (int j = 0; j < loc::kGeometryTerms; ++j) cov.mutable_at(i, j) = c.geometry_covariance(i, j);
  d["geometry_covariance"] = cov;
  auto notes = [](const std::vector<loc::AntennaCalibration::TermNote>& list) {
    pyb::list out;
    for (const auto& n : list) {
      pyb::dict e;
      e["term"] = n.term;
      e["why"] = n.why;
      out.append(e);
    }
    return out;
  };
  d["not_fitted"] = notes(c.not_fitted);
  d["carrier_offsets_not_fitted"] =
      c.carriers_not_fitted.empty() ? pyb::object(pyb::none()) : pyb::object(pyb::str(c.carriers_not_fitted));
  d["prior_bounded"] = notes(c.prior_bounded);
  d["aliased"] = notes(c.aliased);
  if (c.has_allowance()) {
    pyb::dict a;
    a["base_rad"] = c.allowance_base_rad;
    a["smooth_factor"] = c.allowance_smooth_factor;
    a["samples"] = c.allowance_samples;
    a["coverage"] = c.allowance_coverage;
    pyb::list bands;  // per band of tag spacing (AntennaCalibration::allowance_bands)
    for (const auto& b : c.allowance_bands) {
      pyb::dict e;
      e["spacing_from_m"] = b.spacing_from_m;
      e["spacing_below_m"] = float_or_none(b.spacing_below_m);
      e["base_rad"] = b.base_rad;
      e["smooth_factor"] = b.smooth_factor;
      e["samples"] = b.samples;
      e["coverage"] = float_or_none(b.coverage);
      bands.append(e);
    }
    a["bands"] = bands;
    d["allowance"] = a;
  } else {
    d["allowance"] = pyb::none();
  }
  auto localized = [](int tags, double with_m, double without_m, bool helps) -> pyb::object {
    if (tags == 0) return pyb::none();
    pyb::dict e;
    e["tags"] = tags;
    e["median_error_m"] = with_m;
    e["median_error_uncalibrated_m"] = without_m;
    e["helps"] = helps;
    return e;
  };
  d["references_localized"] = localized(c.reference_error_tags, c.reference_median_error_m,
                                        c.reference_median_error_uncalibrated_m, c.helps_its_references());
  d["held_out"] = localized(c.held_out_tags, c.held_out_median_error_m, c.held_out_median_error_uncalibrated_m,
                            c.helps_held_out());
  if (!d["held_out"].is_none()) {
    d["held_out"]["runs"] = c.held_out_runs;
    d["held_out"]["folds"] = c.held_out_folds;
    pyb::list models;
    for (const auto& m : c.held_out_models) {
      pyb::dict e;
      e["terms"] = m.terms;
      e["median_error_m"] = float_or_none(m.median_error_m);
      e["kept"] = m.kept;
      models.append(e);
    }
    d["held_out"]["models"] = models;
  }
  d["residual_rms_rad"] = float_or_none(c.residual_rms_rad);
  d["reads_used"] = c.reads_used;
  d["tags_used"] = c.tags_used;
  return d;
}

}  // namespace

void bind_calibrate(pyb::module_& m) {
  m.def("_calibrate", &run_calibrate, pyb::arg("references"), pyb::arg("antenna"), pyb::arg("height_known"),
        pyb::arg("fold_pi"), pyb::arg("output"));
}

}  // namespace rfidray::py
