#include "io/coverage_csv.h"

#include <charconv>
#include <cmath>

namespace rfidray::io {
namespace {

// Fixed notation with `precision` decimals: std::to_chars rounds as printf's %.Nf does (the C++17 contract), a
// few times faster than snprintf, which matters for maps of 10⁶ cells.
void field(std::string& line, int precision, double v) {
  line += ',';
  if (!std::isfinite(v)) return;
  char buf[352];  // the longest fixed double (309 digits) with its decimals
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, precision);
  if (ec != std::errc()) return;
  // "-0.000…" would differ from "0.000…" for the same cell on another path: print zeros unsigned.
  if (buf[0] == '-') {
    bool zero = true;
    for (const char* c = buf + 1; c != end; ++c)
      if (*c != '0' && *c != '.') zero = false;
    if (zero) {
      line.append(buf + 1, end);
      return;
    }
  }
  line.append(buf, end);
}

}  // namespace

void write_coverage_csv(std::ostream& out, const std::vector<std::string>& antenna_names, const planning::CoverageCells& cells,
                        const std::vector<planning::CoverageValues>& values) {
  out << kCoverageCsvHeader << '\n';
  std::string line;
  for (size_t a = 0; a < values.size(); ++a) {
    const planning::CoverageValues& v = values[a];
    for (size_t i = 0; i < cells.size(); ++i) {
      line = antenna_names[a];
      const Vec3& p = cells.poses[i].position;
      field(line, 4, p.x());
      field(line, 4, p.y());
      field(line, 4, p.z());
      field(line, 6, v.read_probability[i]);
      field(line, 3, v.rssi_dbm[i]);
      field(line, 5, v.phase_error_rad[i]);
      field(line, 6, v.localization_bound_m[i]);
      field(line, 0, v.outside_validity[i]);
      field(line, 3, v.validity_error[i]);
      line += '\n';
      out << line;
    }
  }
}

}  // namespace rfidray::io
