#pragma once
// Readings and ground truth as the Python API passes them to the extension: readings as the readings CSV's
// columns (a dict of lists/arrays, from load_readings, simulate or the user's own arrays), checked here as the
// CSV reader checks a file; truth as a truth CSV path, or a dict name → (x, y, z). Throw InputError naming the
// argument, row and column.
#include <map>
#include <string>
#include <vector>

#include "io/readings_csv.h"
#include "python/bindings/bindings.h"

namespace rfidray::py {

// The rows of readings[file] (`file` only names it in errors).
std::vector<io::ReadingRow> rows_from(const pyb::dict& columns, size_t file);
// None → empty; str → read_truth_csv; dict name → 3 finite numbers.
std::map<std::string, Vec3> truth_from(pyb::handle truth);

}  // namespace rfidray::py
