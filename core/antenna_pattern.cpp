#include "core/antenna_pattern.h"

#include <algorithm>
#include <cmath>
#include <tuple>

#include "core/error.h"
#include "core/limits.h"
#include "core/units.h"

namespace rfidray {
namespace {

double cos_angle(const Vec3& a, const Vec3& b) {
  const double n = a.norm() * b.norm();
  return n > 0.0 ? std::clamp(a.dot(b) / n, -1.0, 1.0) : 1.0;
}

// Index i such that v[i] <= x <= v[i+1] (clamped), and the interpolation weight.
std::pair<size_t, double> bracket(const std::vector<double>& v, double x) {
  if (v.size() == 1 || x <= v.front()) return {0, 0.0};
  if (x >= v.back()) return {v.size() - 2, 1.0};
  const size_t i = static_cast<size_t>(std::upper_bound(v.begin(), v.end(), x) - v.begin()) - 1;
  return {i, (x - v[i]) / (v[i + 1] - v[i])};
}

// Azimuth columns (ia0, ia1) and weight of ia1. Azimuth is periodic: between the last and the first column
// the gap across ±180° (last → first + 360°) is interpolated too, unless the grid already spans 360°.
std::tuple<size_t, size_t, double> azimuth_bracket(const std::vector<double>& az, double x) {
  const size_t n = az.size();
  if (n == 1) return {0, 0, 0.0};
  if (x >= az.front() && x <= az.back()) {
    const auto [i, w] = bracket(az, x);
    return {i, i + 1, w};
  }
  const double gap = az.front() + 360.0 - az.back();
  if (gap <= 0.0) return x < az.front() ? std::tuple{size_t{0}, size_t{0}, 0.0} : std::tuple{n - 1, n - 1, 0.0};
  const double past_last = x > az.back() ? x - az.back() : x + 360.0 - az.back();
  return {n - 1, 0, past_last / gap};
}

// Bilinear in (azimuth, elevation), interpolating the dBi values; elevation clamps at the table's edges.
double table_gain_dbi(const PatternTable& t, const Vec3& d) {
  const double az = std::atan2(d.y(), d.x()) * 180.0 / kPi;
  const double el = std::atan2(d.z(), std::hypot(d.x(), d.y())) * 180.0 / kPi;
  const size_t naz = t.azimuth_deg.size();
  auto at = [&](size_t ie, size_t ia) { return t.gain_dbi[ie * naz + ia]; };
  const auto [ie, we] = bracket(t.elevation_deg, el);
  const auto [ia, ia1, wa] = azimuth_bracket(t.azimuth_deg, az);
  const size_t ie1 = std::min(ie + 1, t.elevation_deg.size() - 1);
  const double g0 = at(ie, ia) * (1 - wa) + at(ie, ia1) * wa;
  const double g1 = at(ie1, ia) * (1 - wa) + at(ie1, ia1) * wa;
  return g0 * (1 - we) + g1 * we;
}

}  // namespace

double AntennaPattern::patch_exponent() const {
  if (beamwidth_deg > 0.0) {
    // cos^n(θ_3dB / 2) = 1/2
    return std::log(0.5) / std::log(std::cos(0.5 * beamwidth_deg * kPi / 180.0));
  }
  // A cos^n power pattern over the front hemisphere has directivity 2(n + 1).
  return std::max(0.0, db_to_linear(peak_gain_dbi) / 2.0 - 1.0);
}

double AntennaPattern::gain_linear(const Vec3& d) const {
  // 0 dBi is the common case (isotropic test antennas, default tags): no exponential per path.
  const double peak = peak_gain_dbi == 0.0 ? 1.0 : db_to_linear(peak_gain_dbi);
  switch (kind) {
    case PatternKind::kIsotropic:
      return peak;
    case PatternKind::kDipole: {
      // Half-wave dipole along local Z: G(θ) = 1.64 · [cos(π/2 · cos θ) / sin θ]²  (Balanis eq. 4-87/4-91)
      const double c = cos_angle(d, Vec3::UnitZ());
      const double s2 = 1.0 - c * c;
      if (s2 < 1e-12) return 0.0;
      const double f = std::cos(0.5 * kPi * c);
      return 1.64 * f * f / s2;
    }
    case PatternKind::kPatch: {
      const double c = cos_angle(d, Vec3::UnitX());
      const double floor = peak * db_to_linear(-front_to_back_db);
      if (c <= 0.0) return floor;
      return std::max(floor, peak * std::pow(c, patch_exponent()));
    }
    case PatternKind::kTable:
      return db_to_linear(table_gain_dbi(*table, d));
  }
  return peak;
}

double AntennaPattern::max_gain_linear() const {
  const double peak = peak_gain_dbi == 0.0 ? 1.0 : db_to_linear(peak_gain_dbi);
  switch (kind) {
    case PatternKind::kIsotropic:
      return peak;
    case PatternKind::kDipole:
      return 1.64;  // broadside: cos²(π/2·cos θ)/sin²θ ≤ 1, equal at θ = 90°
    case PatternKind::kPatch:
      return std::max(peak, peak * db_to_linear(-front_to_back_db));  // boresight (the floor is below it)
    case PatternKind::kTable:
      return db_to_linear(*std::max_element(table->gain_dbi.begin(), table->gain_dbi.end()));
  }
  return peak;
}

void AntennaPattern::validate(const std::string& field) const {
  limits::check_range(peak_gain_dbi, -limits::kMaxGainDbi, limits::kMaxGainDbi, field + ".gain_dbi", "dBi");
  if (kind == PatternKind::kPatch) {
    if (!(beamwidth_deg >= 0.0 && beamwidth_deg < 180.0))
      throw field_error(field + ".beamwidth_deg", "must be in [0, 180) degrees");
    if (beamwidth_deg == 0.0 && peak_gain_dbi <= linear_to_db(2.0))
      throw field_error(field + ".gain_dbi", "a patch without beamwidth needs a gain above 3 dBi");
    limits::check_range(front_to_back_db, 0.0, 200.0, field + ".front_to_back_db", "dB");
  }
  if (kind == PatternKind::kTable) {
    if (!table) throw field_error(field + ".table", "a table pattern needs a table");
    const auto& t = *table;
    if (t.azimuth_deg.empty() || t.elevation_deg.empty() ||
        t.gain_dbi.size() != t.azimuth_deg.size() * t.elevation_deg.size())
      throw field_error(field + ".table", "needs elevation × azimuth gains (rows × columns)");
    auto increasing = [](const std::vector<double>& v) {
      return std::adjacent_find(v.begin(), v.end(), std::greater_equal<>()) == v.end();
    };
    if (!increasing(t.azimuth_deg) || !increasing(t.elevation_deg))
      throw field_error(field + ".table", "azimuth and elevation must be strictly increasing");
    if (t.azimuth_deg.front() < -180.0 || t.azimuth_deg.back() > 180.0 || t.elevation_deg.front() < -90.0 ||
        t.elevation_deg.back() > 90.0)
      throw field_error(field + ".table", "azimuth must lie in [-180, 180] and elevation in [-90, 90] degrees");
    for (double g : t.gain_dbi)
      limits::check_range(g, -limits::kMaxGainDbi, limits::kMaxGainDbi, field + ".table", "dBi");
  }
}

AntennaPattern isotropic_pattern(double gain_dbi) {
  AntennaPattern p;
  p.peak_gain_dbi = gain_dbi;
  return p;
}

PatternKind parse_pattern_kind(const std::string& name, const std::string& field) {
  if (name == "isotropic") return PatternKind::kIsotropic;
  if (name == "dipole") return PatternKind::kDipole;
  if (name == "patch") return PatternKind::kPatch;
  if (name == "table") return PatternKind::kTable;
  throw field_error(field, "unknown pattern '" + clip(name) + "' (isotropic, dipole, patch, table)");
}

const char* to_string(PatternKind kind) {
  switch (kind) {
    case PatternKind::kIsotropic: return "isotropic";
    case PatternKind::kDipole: return "dipole";
    case PatternKind::kPatch: return "patch";
    case PatternKind::kTable: return "table";
  }
  return "?";
}

}  // namespace rfidray
