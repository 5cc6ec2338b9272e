#include "io/tag_antenna_spec.h"

#include <cmath>
#include <fstream>
#include <sstream>

#include "core/error.h"
#include "io/csv_fields.h"

namespace rfidray::io {
namespace {

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> out;
  std::string part;
  std::istringstream s(text);
  while (std::getline(s, part, sep)) out.push_back(trim(part));
  if (!text.empty() && text.back() == sep) out.emplace_back();
  return out;
}

double number(const std::string& text, const std::string& field, const std::string& what) {
  const auto v = to_number(text);
  if (!v || !std::isfinite(*v)) throw field_error(field, what + " must be a finite number (got '" + clip(text) + "')");
  return *v;
}

}  // namespace

TagAntennaSpec parse_tag_antenna(const std::string& text, const std::string& field) {
  const auto p = split(text, ':');
  TagAntennaSpec a;
  if (!p.empty() && p[0] == "dipole" && (p.size() == 3 || p.size() == 4)) {
    a.kind = TagAntennaSpec::Kind::kDipole;
    a.dipole.length_m = number(p[1], field, "the length (m)");
    a.dipole.radius_m = number(p[2], field, "the radius (m)");
    if (p.size() == 4) a.dipole.conductivity_s_m = number(p[3], field, "the conductivity (S/m)");
    return a;
  }
  if (!p.empty() && p[0] == "table" && text.size() > 6) {
    a.kind = TagAntennaSpec::Kind::kTable;
    a.table_source = text.substr(6);
    a.table = read_tag_antenna_table(a.table_source);
    return a;
  }
  throw field_error(field, "'" + clip(text) +
                               "': expected dipole:LENGTH_M:RADIUS_M[:CONDUCTIVITY_S_M] or table:FILE.csv");
}

TagChipSpec parse_tag_chip(const std::string& text, const std::string& field) {
  const auto p = split(text, ':');
  TagChipSpec c;
  if (!p.empty() && p[0] == "matched" && p.size() <= 2) {
    if (p.size() == 2) c.design_frequency_hz = number(p[1], field, "the design frequency (Hz)");
    return c;
  }
  if (p.size() == 3 && (p[0] == "series" || p[0] == "parallel")) {
    c.kind = p[0] == "series" ? TagChipSpec::Kind::kSeries : TagChipSpec::Kind::kParallel;
    c.resistance_ohm = number(p[1], field, "the resistance (Ω)");
    c.capacitance_f = number(p[2], field, "the capacitance (F)");
    return c;
  }
  throw field_error(field, "'" + clip(text) +
                               "': expected matched[:DESIGN_FREQUENCY_HZ], series:R_OHM:C_F or parallel:R_OHM:C_F");
}

TagBackingSpec parse_tag_backing(const std::string& text, const std::string& field) {
  TagBackingSpec m;
  if (text == "none") return m;
  if (text == "scene") {
    m.kind = TagBackingSpec::Kind::kScene;
    return m;
  }
  const auto p = split(text, ':');
  if (p.size() == 2 && !p[0].empty()) {
    m.kind = TagBackingSpec::Kind::kGiven;
    m.material = backing_material(p[0], field + ".material");
    m.distance_m = number(p[1], field, "the distance (m)");
    return m;
  }
  if (p.size() == 4 && p[0] == "dielectric") {
    m.kind = TagBackingSpec::Kind::kGiven;
    const double eps_r = number(p[1], field, "the relative permittivity");
    const double sigma_s_m = number(p[2], field, "the conductivity (S/m)");
    if (!(eps_r >= 1.0)) throw field_error(field, "'" + clip(text) + "': the relative permittivity must be >= 1");
    if (!(sigma_s_m >= 0.0)) throw field_error(field, "'" + clip(text) + "': the conductivity must be >= 0 S/m");
    m.material = user_material("dielectric", eps_r, sigma_s_m, 0.0);
    m.distance_m = number(p[3], field, "the distance (m)");
    return m;
  }
  throw field_error(field, "'" + clip(text) +
                               "': expected none, scene, MATERIAL:DISTANCE_M (e.g. metal:0.01, water:0.005) or "
                               "dielectric:EPS_R:SIGMA_S_M:DISTANCE_M");
}

std::vector<TagAntennaSpec::Point> read_tag_antenna_table(const std::string& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file + ": cannot read the tag antenna table");
  std::vector<TagAntennaSpec::Point> rows;
  std::string line;
  int n = 0;
  bool header = true;
  while (std::getline(in, line)) {
    ++n;
    if (n == 1) strip_bom(line);
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    const auto cols = split(t, ',');
    if (header) {
      header = false;
      if (cols.size() == 3 && normalized_name(cols[0]) == "frequencyhz" && normalized_name(cols[1]) == "resistanceohm" &&
          normalized_name(cols[2]) == "reactanceohm")
        continue;
      throw InputError(located(file, n) + "the header must be frequency_hz,resistance_ohm,reactance_ohm");
    }
    if (cols.size() != 3) throw InputError(located(file, n) + "needs 3 columns (got " + std::to_string(cols.size()) + ")");
    TagAntennaSpec::Point p;
    p.frequency_hz = parse_finite(cols[0], file, n, "frequency_hz");
    p.impedance_ohm = {parse_finite(cols[1], file, n, "resistance_ohm"), parse_finite(cols[2], file, n, "reactance_ohm")};
    if (!(p.frequency_hz > 0.0) || (!rows.empty() && !(p.frequency_hz > rows.back().frequency_hz)))
      throw InputError(located(file, n) + "column 'frequency_hz': must be > 0 and increasing");
    if (!(p.impedance_ohm.real() > 0.0))
      throw InputError(located(file, n) + "column 'resistance_ohm': must be > 0");
    rows.push_back(p);
    if (rows.size() > 100000) throw InputError(file + ": more than 100000 rows");
  }
  if (rows.empty()) throw InputError(file + ": no rows (header frequency_hz,resistance_ohm,reactance_ohm, then one row per frequency)");
  return rows;
}

}  // namespace rfidray::io
