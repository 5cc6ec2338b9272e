#include "io/coverage_csv.h"

#include <cmath>
#include <cstdio>

namespace rfidray::io {
namespace {

void field(std::string& line, const char* format, double v) {
  line += ',';
  if (!std::isfinite(v)) return;
  char buf[48];
  std::snprintf(buf, sizeof buf, format, v);
  // "-0.000…" would differ from "0.000…" for the same cell on another path: print zeros unsigned.
  if (buf[0] == '-') {
    bool zero = true;
    for (const char* c = buf + 1; *c; ++c)
      if (*c != '0' && *c != '.') zero = false;
    if (zero) {
      line += buf + 1;
      return;
    }
  }
  line += buf;
}

}  // namespace

void write_coverage_csv(std::ostream& out, const std::vector<std::string>& antenna_names, const CoverageCells& cells,
                        const std::vector<CoverageValues>& values) {
  out << kCoverageCsvHeader << '\n';
  std::string line;
  for (size_t a = 0; a < values.size(); ++a) {
    const CoverageValues& v = values[a];
    for (size_t i = 0; i < cells.size(); ++i) {
      line = antenna_names[a];
      const Vec3& p = cells.poses[i].position;
      field(line, "%.4f", p.x());
      field(line, "%.4f", p.y());
      field(line, "%.4f", p.z());
      field(line, "%.6f", v.read_probability[i]);
      field(line, "%.3f", v.rssi_dbm[i]);
      field(line, "%.5f", v.phase_error_rad[i]);
      field(line, "%.6f", v.localization_bound_m[i]);
      line += '\n';
      out << line;
    }
  }
}

}  // namespace rfidray::io
