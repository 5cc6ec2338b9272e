#include "io/antenna_file.h"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "io/checked_yaml.h"
#include "core/number_text.h"

namespace rfidray::io {

namespace {

std::string list(const std::vector<double>& v) {
  std::string s = "[";
  for (size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + num(v[i]);
  return s + "]";
}

// A YAML double-quoted scalar that reads back to `text`: quote and backslash escaped, control characters as \xNN
// (a raw line break inside quotes would be folded to a space).
std::string yaml_quoted(const std::string& text) {
  std::string q = "\"";
  for (const char ch : text) {
    const unsigned char u = static_cast<unsigned char>(ch);
    if (ch == '"' || ch == '\\') {
      q += '\\';
      q += ch;
    } else if (u < 0x20 || u == 0x7f) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02x", u);
      q += hex;
    } else {
      q += ch;
    }
  }
  return q + "\"";
}

// An optional count under `key` of `map` (0 when absent), named by its field when not a count.
int count_in(const YamlFile& src, YamlMap& map, const char* key) {
  auto n = map.get(key);
  if (!n) return 0;
  const long long v = src.integer(*n, map.field(key));
  if (v < 0 || v > 2000000000LL) throw src.error(*n, map.field(key), "must be a count >= 0");
  return static_cast<int>(v);
}

loc::AntennaCalibration parse_node(const YAML::Node& root, const std::string& source) {
  const YamlFile src(source);
  if (!root.IsDefined() || root.IsNull()) throw InputError(source + ": empty antenna file");
  YamlMap m(src, root, "");
  loc::AntennaCalibration c;
  c.antenna = src.scalar(m.required("antenna"), "antenna");
  c.phase_centre_offset_m = src.point(m.required("phase_centre_offset_m"), "phase_centre_offset_m");
  if (auto n = m.get("phase_centre_offset_sd_m")) c.phase_centre_offset_sd_m = src.point(*n, "phase_centre_offset_sd_m");
  const YAML::Node fn = m.required("frequencies_hz");
  c.frequencies_hz = src.numbers(fn, "frequencies_hz");
  // Empty: no carrier offsets calibrated (calibrate kept nothing: carrier_offsets_not_fitted says why).
  for (size_t i = 0; i < c.frequencies_hz.size(); ++i) {
    if (c.frequencies_hz[i] <= 0.0)
      throw src.error(fn[i], "frequencies_hz[" + std::to_string(i) + "]", "must be > 0 (got " + num(c.frequencies_hz[i]) + ")");
    if (i > 0 && c.frequencies_hz[i] <= c.frequencies_hz[i - 1])
      throw src.error(fn[i], "frequencies_hz[" + std::to_string(i) + "]", "must be ascending and distinct");
  }
  const YAML::Node on = m.required("carrier_offsets_rad");
  c.carrier_offsets_rad = src.numbers(on, "carrier_offsets_rad");
  if (c.carrier_offsets_rad.size() != c.frequencies_hz.size())
    throw src.error(on, "carrier_offsets_rad", "needs one value per frequency (" + std::to_string(c.frequencies_hz.size()) +
                                                   "), got " + std::to_string(c.carrier_offsets_rad.size()));
  if (!c.carrier_offsets_rad.empty() && c.carrier_offsets_rad[0] != 0.0) throw src.error(on[0], "carrier_offsets_rad[0]", "must be 0 (offsets are relative to the first carrier)");
  c.carrier_offsets_sd_rad.assign(c.frequencies_hz.size(), 0.0);
  if (auto n = m.get("carrier_offsets_sd_rad")) {
    c.carrier_offsets_sd_rad = src.numbers(*n, "carrier_offsets_sd_rad");
    if (c.carrier_offsets_sd_rad.size() != c.frequencies_hz.size())
      throw src.error(*n, "carrier_offsets_sd_rad", "needs one value per frequency");
  }
  const YAML::Node tn = m.required("pattern_terms");
  if (!tn.IsSequence() || tn.size() != loc::kPatternTerms)
    throw src.error(tn, "pattern_terms", "must be the list [az, el, az2, az_el, el2]");
  for (int t = 0; t < loc::kPatternTerms; ++t)
    if (src.scalar(tn[t], "pattern_terms[" + std::to_string(t) + "]") != loc::kPatternTermNames[t])
      throw src.error(tn[t], "pattern_terms[" + std::to_string(t) + "]",
                      std::string("must be '") + loc::kPatternTermNames[t] + "' (the basis is fixed: az, el, az2, az_el, el2)");
  auto pattern = [&](const char* key, std::array<double, loc::kPatternTerms>& out, bool required) {
    auto n = required ? std::optional<YAML::Node>(m.required(key)) : m.get(key);
    if (!n) return;
    const std::vector<double> v = src.numbers(*n, key);
    if (v.size() != loc::kPatternTerms) throw src.error(*n, key, "needs " + std::to_string(loc::kPatternTerms) + " numbers");
    std::copy(v.begin(), v.end(), out.begin());
  };
  pattern("pattern_rad", c.pattern_rad, true);
  pattern("pattern_sd_rad", c.pattern_sd_rad, false);
  if (auto n = m.get("geometry_covariance")) {
    // kGeometryTerms rows of kGeometryTerms numbers, symmetric, positive semi-definite.
    const char* key = "geometry_covariance";
    if (!n->IsSequence() || n->size() != loc::kGeometryTerms)
      throw src.error(*n, key, "must be " + std::to_string(loc::kGeometryTerms) + " rows of " +
                                   std::to_string(loc::kGeometryTerms) + " numbers (dx, dy, dz, az, el, az2, az_el, el2)");
    for (int i = 0; i < loc::kGeometryTerms; ++i) {
      const std::string row = std::string(key) + "[" + std::to_string(i) + "]";
      const std::vector<double> v = src.numbers((*n)[i], row);
      if (v.size() != loc::kGeometryTerms)
        throw src.error((*n)[i], row, "needs " + std::to_string(loc::kGeometryTerms) + " numbers");
      for (int j = 0; j < loc::kGeometryTerms; ++j) c.geometry_covariance(i, j) = v[j];
    }
    const loc::GeometryCovariance& g = c.geometry_covariance;
    const double scale = g.diagonal().cwiseAbs().maxCoeff();
    if (!((g - g.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * scale))
      throw src.error(*n, key, "must be symmetric");
    const Eigen::SelfAdjointEigenSolver<loc::GeometryCovariance> eig(g);
    if (eig.eigenvalues().minCoeff() < -1e-8 * scale)  // the file's 10 digits round it
      throw src.error(*n, key, "must be positive semi-definite (smallest eigenvalue " + num(eig.eigenvalues().minCoeff()) + ")");
  }
  // Notes of the calibration on terms it could not determine (optional): [{term, why}], term a geometry term.
  auto notes = [&](const char* key, std::vector<loc::AntennaCalibration::TermNote>& out) {
    auto n = m.get(key);
    if (!n) return;
    if (!n->IsSequence()) throw src.error(*n, key, "must be a list of {term, why}");
    for (size_t i = 0; i < n->size(); ++i) {
      const std::string item = std::string(key) + "[" + std::to_string(i) + "]";
      YamlMap e(src, (*n)[i], item);
      const std::string term = src.scalar(e.required("term"), e.field("term"));
      if (std::none_of(std::begin(loc::kGeometryTermNames), std::end(loc::kGeometryTermNames),
                       [&](const char* t) { return term == t; }))
        throw src.error((*n)[i], e.field("term"), "must be one of dx, dy, dz, az, el, az2, az_el, el2 (got '" + term + "')");
      std::string why;
      if (auto w = e.get("why")) why = src.scalar(*w, e.field("why"));
      e.finish();
      out.push_back({term, why});
    }
  };
  notes("not_fitted", c.not_fitted);
  if (auto n = m.get("carrier_offsets_not_fitted")) {
    c.carriers_not_fitted = src.scalar(*n, "carrier_offsets_not_fitted");
    if (!c.frequencies_hz.empty())
      throw src.error(*n, "carrier_offsets_not_fitted", "is for a file without carriers (frequencies_hz: [])");
  }
  if (auto n = m.get("allowance")) {
    YamlMap a(src, *n, "allowance");
    c.allowance_base_rad = a.non_negative({"base_rad"}, 0.0);
    c.allowance_smooth_factor = a.non_negative({"smooth_factor"}, 1.0);
    c.allowance_samples = count_in(src, a, "samples");
    if (auto k = a.get("coverage")) c.allowance_coverage = a.non_negative({"coverage"}, 0.0);
    // Per band of tag spacing (optional): [{spacing_from_m, spacing_below_m (absent: no upper end), base_rad,
    // smooth_factor, samples, coverage}], ascending and disjoint.
    if (auto bands = a.get("bands")) {
      const std::string key = a.field("bands");
      if (!bands->IsSequence()) throw src.error(*bands, key, "must be a list of {spacing_from_m, spacing_below_m, base_rad, smooth_factor}");
      for (size_t i = 0; i < bands->size(); ++i) {
        const std::string item = key + "[" + std::to_string(i) + "]";
        YamlMap e(src, (*bands)[i], item);
        loc::AntennaCalibration::AllowanceBand b;
        b.spacing_from_m = e.non_negative({"spacing_from_m"}, 0.0);
        if (e.has("spacing_below_m")) b.spacing_below_m = e.non_negative({"spacing_below_m"}, 0.0);
        if (!(b.spacing_below_m > b.spacing_from_m))
          throw src.error((*bands)[i], e.field("spacing_below_m"), "must be above spacing_from_m (" + num(b.spacing_from_m) + ")");
        if (!c.allowance_bands.empty() && b.spacing_from_m < c.allowance_bands.back().spacing_below_m)
          throw src.error((*bands)[i], e.field("spacing_from_m"),
                          "bands must be ascending and disjoint (the band before ends at " +
                              num(c.allowance_bands.back().spacing_below_m) + ")");
        b.base_rad = e.non_negative({"base_rad"}, 0.0);
        b.smooth_factor = e.non_negative({"smooth_factor"}, 0.0);
        b.samples = count_in(src, e, "samples");
        if (e.has("coverage")) b.coverage = e.non_negative({"coverage"}, 0.0);
        e.finish();
        c.allowance_bands.push_back(b);
      }
    }
    a.finish();
  }
  notes("prior_bounded", c.prior_bounded);
  c.residual_rms_rad = m.non_negative({"residual_rms_rad"}, std::numeric_limits<double>::quiet_NaN());
  c.reads_used = count_in(src, m, "reads_used");
  c.tags_used = count_in(src, m, "tags_used");
  auto sd_check = [&](const char* key, double v) {
    if (v < 0.0) throw src.error(root, key, "standard deviations must be >= 0");
  };
  for (int a = 0; a < 3; ++a) sd_check("phase_centre_offset_sd_m", c.phase_centre_offset_sd_m[a]);
  for (double v : c.carrier_offsets_sd_rad) sd_check("carrier_offsets_sd_rad", v);
  for (double v : c.pattern_sd_rad) sd_check("pattern_sd_rad", v);
  m.finish();
  return c;
}

}  // namespace

loc::AntennaCalibration parse_antenna_yaml(const std::string& text, const std::string& source) {
  return parse_node(parse_yaml_text(text, source), source);
}

loc::AntennaCalibration read_antenna_file(const std::string& path) {
  return parse_node(load_yaml_file(path, "antenna file"), path);
}

void write_antenna_file(std::ostream& out, const loc::AntennaCalibration& c) {
  auto vec = [](const Vec3& v) { return list({v.x(), v.y(), v.z()}); };
  auto arr = [](const std::array<double, loc::kPatternTerms>& a) { return list(std::vector<double>(a.begin(), a.end())); };
  out << "# rfidray antenna calibration (rfidray calibrate); model: localization/antenna_calibration.h\n";
  out << "antenna: " << yaml_quoted(c.antenna) << "\n";
  out << "phase_centre_offset_m: " << vec(c.phase_centre_offset_m) << "   # antenna frame, boresight +X\n";
  out << "phase_centre_offset_sd_m: " << vec(c.phase_centre_offset_sd_m) << "\n";
  out << "frequencies_hz: " << list(c.frequencies_hz)
      << (c.frequencies_hz.empty() ? "   # none calibrated: each carrier keeps its own offset\n" : "\n");
  out << "carrier_offsets_rad: " << list(c.carrier_offsets_rad) << "   # relative to the first carrier\n";
  out << "carrier_offsets_sd_rad: " << list(c.carrier_offsets_sd_rad) << "\n";
  out << "pattern_terms: [";
  for (int t = 0; t < loc::kPatternTerms; ++t) out << (t ? ", " : "") << loc::kPatternTermNames[t];
  out << "]\n";
  out << "pattern_rad: " << arr(c.pattern_rad) << "\n";
  out << "pattern_sd_rad: " << arr(c.pattern_sd_rad) << "\n";
  if (!c.geometry_covariance.isZero(0.0)) {
    out << "geometry_covariance:   # rows and columns: dx, dy, dz (m), az, el, az2, az_el, el2 (rad)\n";
    for (int i = 0; i < loc::kGeometryTerms; ++i) {
      std::vector<double> row(loc::kGeometryTerms);
      for (int j = 0; j < loc::kGeometryTerms; ++j) row[j] = c.geometry_covariance(i, j);
      out << "  - " << list(row) << "\n";
    }
  }
  if (!c.not_fitted.empty()) {
    out << "not_fitted:   # held at 0 (sd 0): the reference geometry does not determine them\n";
    for (const auto& n : c.not_fitted) out << "  - {term: " << n.term << ", why: " << yaml_quoted(n.why) << "}\n";
  }
  if (!c.carriers_not_fitted.empty()) out << "carrier_offsets_not_fitted: " << yaml_quoted(c.carriers_not_fitted) << "\n";
  if (c.has_allowance()) {
    out << "allowance:   # radius allowance measured on the reference tags: sigma_sys = max(base, factor x smooth misfit)\n";
    out << "  base_rad: " << num(c.allowance_base_rad) << "\n";
    out << "  smooth_factor: " << num(c.allowance_smooth_factor) << "\n";
    out << "  samples: " << c.allowance_samples << "\n";
    if (std::isfinite(c.allowance_coverage)) out << "  coverage: " << num(c.allowance_coverage) << "\n";
    if (!c.allowance_bands.empty()) {
      out << "  bands:   # the same measured per band of tag spacing (nearest neighbour, m); localize --tag-spacing-m picks one\n";
      for (const auto& b : c.allowance_bands) {
        out << "    - {spacing_from_m: " << num(b.spacing_from_m);
        if (std::isfinite(b.spacing_below_m)) out << ", spacing_below_m: " << num(b.spacing_below_m);
        out << ", base_rad: " << num(b.base_rad) << ", smooth_factor: " << num(b.smooth_factor) << ", samples: " << b.samples;
        if (std::isfinite(b.coverage)) out << ", coverage: " << num(b.coverage);
        out << "}\n";
      }
    }
  }
  if (!c.prior_bounded.empty()) {
    out << "prior_bounded:   # fitted, but their sd is nearly the prior's: the data hardly determine them\n";
    for (const auto& n : c.prior_bounded) out << "  - {term: " << n.term << ", why: " << yaml_quoted(n.why) << "}\n";
  }
  if (std::isfinite(c.residual_rms_rad)) out << "residual_rms_rad: " << num(c.residual_rms_rad) << "\n";  // NaN: no fit
  out << "reads_used: " << c.reads_used << "\n";
  out << "tags_used: " << c.tags_used << "\n";
}

void label_groups_by_antenna(std::vector<loc::TagReads>& tags) {
  for (loc::TagReads& t : tags)
    for (loc::ReadGroup& g : t.groups) {
      const size_t colon = g.antenna.find(':');
      if (g.antenna.rfind("file", 0) != 0) continue;  // not a group_by_tag label
      if (colon == std::string::npos) {
        g.antenna.clear();
        continue;
      }
      const size_t slash = g.antenna.rfind('/');
      g.antenna = g.antenna.substr(colon + 1, slash == std::string::npos || slash < colon ? std::string::npos : slash - colon - 1);
    }
}

}  // namespace rfidray::io
