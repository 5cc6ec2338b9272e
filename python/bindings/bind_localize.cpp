// localize(): tag positions from readings, with the options and the per-tag loop of `rfidray localize`
// (io::group_by_tag, io::label_groups_by_antenna, loc::localize). Readings arrive as the CSV's columns
// (readings_arg.h).
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <map>
#include <optional>

#include "core/error.h"
#include "io/antenna_file.h"
#include "io/readings_csv.h"
#include "io/scene_multipath.h"
#include "localization/localize_request.h"
#include "localization/methods.h"
#include "python/bindings/bindings.h"
#include "python/bindings/readings_arg.h"

namespace rfidray::py {
namespace {

// The keyword names of rfidray.localize, for loc::validate's messages.
const loc::LocalizeFieldNames kKeywordNames{
    .method = "method", .mirror_prior = "mirror_prior", .mirror_prior_truth = "mirror_prior='truth'",
    .frequency_hz = "frequency_hz", .max_range_m = "max_range_m", .stride_m = "stride_m",
    .max_residual_rad = "max_residual_rad", .max_uncertainty_m = "max_uncertainty_m",
    .systematic_phase_rad = "systematic_phase_rad", .height_known = "height_known", .truth = "truth",
    .scenario = "scenario", .channel = "channel", .tag_spacing_m = "tag_spacing_m", .antenna_file = "antenna_file"};

pyb::list run_localize(const pyb::list& files, pyb::object truth_arg, const std::string& method,
                       bool height_known, const std::string& mirror_prior, double frequency_hz, double max_range_m,
                       double stride_m, std::optional<std::string> antenna_file, bool fold_pi,
                       double max_residual_rad, double max_uncertainty_m,
                       std::optional<double> systematic_phase_rad,
                       std::optional<std::string> scenario_file, std::optional<std::string> channel,
                       std::optional<double> tag_spacing_m) {
  // The request of `rfidray localize` (localization/localize_request.h), with the keyword names of this API.
  const loc::LocalizeRequest request{.method = method, .mirror_prior = mirror_prior, .frequency_hz = frequency_hz,
                                     .max_range_m = max_range_m, .stride_m = stride_m,
                                     .max_residual_rad = max_residual_rad, .max_uncertainty_m = max_uncertainty_m,
                                     .systematic_phase_rad = systematic_phase_rad, .height_known = height_known,
                                     .tag_spacing_m = tag_spacing_m,
                                     .fold_pi = fold_pi, .has_truth = !truth_arg.is_none(),
                                     .has_antenna_file = antenna_file.has_value(),
                                     .has_scenario = scenario_file.has_value(), .has_channel = channel.has_value()};
  const loc::LocalizeFieldNames& names = kKeywordNames;
  loc::LocalizePlan plan = loc::validate(request, names);
  if (antenna_file) plan.options.calibration = io::read_antenna_file(*antenna_file);
  loc::apply_calibration_allowance(plan, request);
  // The known scene (io/scene_multipath.h), as `rfidray localize --scenario [--channel]`.
  std::optional<io::SceneMultipath> scene;
  if (scenario_file) scene = io::load_scene_multipath(*scenario_file, channel, "channel");
  const std::map<std::string, Vec3> truth = truth_from(truth_arg);

  std::vector<std::vector<io::ReadingRow>> rows;
  for (size_t i = 0; i < files.size(); ++i) rows.push_back(rows_from(files[i].cast<pyb::dict>(), i));
  std::vector<loc::TagReads> tags = io::group_by_tag(rows, frequency_hz);
  io::label_groups_by_antenna(tags);

  struct Item {
    std::string tag;
    loc::Method method;
    loc::LocalizeResult result;
    size_t reads;
    std::optional<double> error_m;
  };
  std::vector<Item> items;
  {
    pyb::gil_scoped_release release;
    for (const loc::TagReads& tag : tags) {
      const loc::LocalizeOptions o =
          loc::tag_options(plan, tag.tag, truth, "truth", names, scene ? scene->allowance_for(tag) : nullptr);
      const auto t = truth.find(tag.tag);
      for (loc::Method m : plan.methods) {
        Item it{tag.tag, m, loc::localize(m, tag, o), tag.read_count(), std::nullopt};
        if (it.result.has_position() && t != truth.end()) it.error_m = (it.result.position - t->second).norm();
        items.push_back(std::move(it));
      }
    }
  }
  // The keys of `rfidray localize --json` results (without time_ms); None where the JSON has null.
  pyb::list out;
  for (const Item& it : items) {
    const loc::LocalizeResult& r = it.result;
    pyb::dict d;
    d["name"] = it.tag;
    d["method"] = loc::to_string(it.method);
    const bool positioned = r.has_position();
    d["status"] = loc::to_string(r.status());
    d["reason"] = r.ok ? pyb::object(pyb::none()) : pyb::object(pyb::str(loc::to_string(r.reason)));
    d["detail"] = r.ok ? pyb::object(pyb::none()) : pyb::object(pyb::str(r.detail));
    d["x"] = positioned ? float_or_none(r.position.x()) : pyb::none();
    d["y"] = positioned ? float_or_none(r.position.y()) : pyb::none();
    d["z"] = positioned ? float_or_none(r.position.z()) : pyb::none();
    d["error_m"] = it.error_m ? pyb::object(pyb::float_(*it.error_m)) : pyb::none();
    d["uncertainty_m"] = positioned ? float_or_none(r.uncertainty_m) : pyb::none();
    d["residual_rad"] = float_or_none(r.residual_rad);
    d["systematic_rad"] = positioned ? float_or_none(r.radius_systematic_rad) : pyb::none();  // σ_sys of the radius
    d["multipath_phase_rad"] = scene ? float_or_none(r.multipath_phase_rad) : pyb::none();
    d["mirror_resolved_by"] = positioned && !r.mirror_resolved_by.empty() ? pyb::object(pyb::str(r.mirror_resolved_by)) : pyb::none();
    d["reads"] = it.reads;
    out.append(d);
  }
  return out;
}

}  // namespace

void bind_localize(pyb::module_& m) {
  m.def("_localize", &run_localize, pyb::arg("files"), pyb::arg("truth"), pyb::arg("method"),
        pyb::arg("height_known"), pyb::arg("mirror_prior"), pyb::arg("frequency_hz"), pyb::arg("max_range_m"),
        pyb::arg("stride_m"), pyb::arg("antenna_file"), pyb::arg("fold_pi"), pyb::arg("max_residual_rad"),
        pyb::arg("max_uncertainty_m"), pyb::arg("systematic_phase_rad"), pyb::arg("scenario"), pyb::arg("channel"),
        pyb::arg("tag_spacing_m"));
}

}  // namespace rfidray::py
