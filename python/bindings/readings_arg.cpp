#include "python/bindings/readings_arg.h"

#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>

#include "core/error.h"
#include "io/checked_yaml.h"

namespace rfidray::py {

std::vector<io::ReadingRow> rows_from(const pyb::dict& columns, size_t file) {
  const std::string where = "readings[" + std::to_string(file) + "]";
  auto column = [&](const char* name) {
    if (!columns.contains(name)) throw InputError(where + ": no column '" + std::string(name) + "'");
    return columns[name].cast<pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>>();
  };
  const char* required[] = {"time", "posx", "posy", "posz", "q1", "q2", "q3", "q4", "phase"};
  std::map<std::string, pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>> num;
  for (const char* c : required) num.emplace(c, column(c));
  if (!columns.contains("name")) throw InputError(where + ": no column 'name'");
  const auto names = columns["name"].cast<std::vector<std::string>>();
  const size_t n = names.size();
  std::optional<std::vector<std::string>> antennas;
  if (columns.contains("antenna")) antennas = columns["antenna"].cast<std::vector<std::string>>();
  std::optional<pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>> frequency, hop;
  if (columns.contains("frequency_hz")) frequency = column("frequency_hz");
  if (columns.contains("channel")) hop = column("channel");
  auto check_size = [&](const std::string& c, pyb::ssize_t size) {
    if (size != static_cast<pyb::ssize_t>(n))
      throw InputError(where + ": column '" + c + "' has " + std::to_string(size) + " rows, 'name' has " + std::to_string(n));
  };
  for (const auto& [c, a] : num) check_size(c, a.size());
  if (antennas) check_size("antenna", static_cast<pyb::ssize_t>(antennas->size()));
  if (frequency) check_size("frequency_hz", frequency->size());
  if (hop) check_size("channel", hop->size());

  std::vector<io::ReadingRow> rows(n);
  for (size_t i = 0; i < n; ++i) {
    io::ReadingRow& r = rows[i];
    r.line = static_cast<int>(i + 1);
    auto value = [&](const char* c, const pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast>& a) {
      const double v = a.at(static_cast<pyb::ssize_t>(i));
      if (!std::isfinite(v)) throw InputError(where + ": row " + std::to_string(i) + ": column '" + c + "': not finite");
      return v;
    };
    r.time_s = value("time", num.at("time"));
    r.antenna_pose.position = Vec3(value("posx", num.at("posx")), value("posy", num.at("posy")), value("posz", num.at("posz")));
    const Quat q(value("q4", num.at("q4")), value("q1", num.at("q1")), value("q2", num.at("q2")), value("q3", num.at("q3")));
    if (q.norm() < 1e-9) throw InputError(where + ": row " + std::to_string(i) + ": quaternion q1..q4 is zero");
    r.antenna_pose.orientation = q.normalized();
    r.tag = names[i];
    if (r.tag.empty()) throw InputError(where + ": row " + std::to_string(i) + ": column 'name': empty");
    r.phase_rad = value("phase", num.at("phase"));
    if (antennas) r.antenna = (*antennas)[i];
    if (frequency) {
      r.frequency_hz = value("frequency_hz", *frequency);
      if (!(r.frequency_hz > 0.0)) throw InputError(where + ": row " + std::to_string(i) + ": column 'frequency_hz': must be > 0");
    }
    if (hop) r.hop_index = static_cast<int>(value("channel", *hop));
  }
  return rows;
}

std::map<std::string, Vec3> truth_from(pyb::handle truth_arg) {
  std::map<std::string, Vec3> truth;
  if (truth_arg.is_none()) return truth;
  if (pyb::isinstance<pyb::str>(truth_arg)) return io::read_truth_csv(truth_arg.cast<std::string>());
  for (auto item : truth_arg.cast<pyb::dict>()) {
    const std::string name = pyb::str(item.first).cast<std::string>();
    const auto p = item.second.cast<std::vector<double>>();
    if (p.size() != 3 || !std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw InputError("truth['" + clip(name) + "']: needs 3 finite numbers x, y, z");
    truth[name] = Vec3(p[0], p[1], p[2]);
  }
  return truth;
}

}  // namespace rfidray::py
