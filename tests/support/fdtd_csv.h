#pragma once
// The FDTD references stored in bench/results/fullwave/CASE.csv (bench/fullwave/run.py): each observer's position,
// kρ and field E/E_free (the finest resolution's Richardson value), read from the file so that a test checks the
// stored reference, not a copy of it. Header-only, for tests.
#include <gtest/gtest.h>

#include <complex>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry.h"

namespace rfidray::testing {

struct FdtdObserver {
  std::string name;
  Vec3 position;
  double krho = 0.0;
  std::complex<double> field;
};

inline std::vector<FdtdObserver> read_fdtd(const std::string& file) {
  std::ifstream in(std::string(RFIDRAY_SOURCE_DIR) + "/bench/results/fullwave/" + file);
  EXPECT_TRUE(in) << file;
  std::string line;
  std::getline(in, line);
  std::map<std::string, size_t> column;
  {
    std::stringstream header(line);
    std::string name;
    for (size_t i = 0; std::getline(header, name, ','); ++i) column[name] = i;
  }
  std::vector<FdtdObserver> out;
  while (std::getline(in, line)) {
    std::vector<std::string> f;  // CSV with one quoted field (the region label)
    std::string cell;
    bool quoted = false;
    for (char ch : line) {
      if (ch == '"') quoted = !quoted;
      else if (ch == ',' && !quoted) f.push_back(std::exchange(cell, ""));
      else cell += ch;
    }
    f.push_back(cell);
    out.push_back({f[0], Vec3(std::stod(f[column["x_m"]]), std::stod(f[column["y_m"]]), std::stod(f[column["z_m"]])),
                   std::stod(f[column["krho"]]),
                   std::polar(std::stod(f[column["fdtd_abs"]]), std::stod(f[column["fdtd_arg_rad"]]))});
  }
  return out;
}

}  // namespace rfidray::testing
