#include "cli/readings_csv.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "core/error.h"

namespace rfidray::cli {
namespace {

// Fixed-point text, correctly rounded (std::to_chars: same digits as printf "%.*f", several times faster);
// values that print as zero print as "0.…" (never "-0.…").
void put(std::ostream& out, double v, int decimals) {
  char buf[400];  // fixed notation of the largest double: 309 digits + decimals
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v, std::chars_format::fixed, decimals);
  if (ec != std::errc()) throw InputError("readings CSV: cannot format value");
  const char* first = buf;
  if (buf[0] == '-' && std::none_of(buf + 1, end, [](char c) { return c >= '1' && c <= '9'; })) ++first;
  out.write(first, end - first);
}

}  // namespace

void write_readings_csv(std::ostream& out, const Scenario& scenario, size_t antenna, const AntennaResult& result) {
  out << kReadingsHeader << '\n';
  write_readings_rows(out, scenario, antenna, result.reads);
}

void write_readings_rows(std::ostream& out, const Scenario& scenario, size_t antenna,
                         const std::vector<ReadRecord>& reads) {
  const std::string& name = scenario.antennas.at(antenna).reader.name;
  for (const ReadRecord& r : reads) {
    const Vec3& p = r.antenna_pose.position;
    const Quat& q = r.antenna_pose.orientation;
    put(out, r.time_s, 6);
    for (double v : {p.x(), p.y(), p.z()}) {
      out << ',';
      put(out, v, 6);
    }
    for (double v : {q.x(), q.y(), q.z(), q.w()}) {
      out << ',';
      put(out, v, 9);
    }
    out << ',' << scenario.tags.at(r.tag).tag.name << ',';
    put(out, r.distance_m, 6);
    out << ',';
    put(out, r.reading.phase_rad, 6);
    out << ',';
    put(out, r.reading.rssi_dbm, 4);
    out << ',' << name << ',';
    put(out, r.frequency_hz, 0);
    out << ',' << r.channel_index << '\n';
  }
}

void write_tags_csv(std::ostream& out, const Scenario& scenario, const SceneMotion& motion) {
  out << "name,x,y,z\n";
  for (size_t i = 0; i < scenario.tags.size(); ++i) {
    const Vec3 p = motion.tags[i]->pose_at(0.0).position;
    out << scenario.tags[i].tag.name;
    for (double v : {p.x(), p.y(), p.z()}) {
      out << ',';
      put(out, v, 6);
    }
    out << '\n';
  }
}

bool has_moving_tags(const SceneMotion& motion) {
  for (const auto& t : motion.tags)
    if (!t->is_static()) return true;
  return false;
}

void write_tag_trajectories_csv(std::ostream& out, const Scenario& scenario, const SceneMotion& motion,
                                double duration_s, double rate_hz) {
  out << "time,name,x,y,z\n";
  const uint64_t n = static_cast<uint64_t>(std::floor(duration_s * rate_hz + 1e-9)) + 1;
  for (uint64_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) / rate_hz;
    for (size_t i = 0; i < scenario.tags.size(); ++i) {
      if (motion.tags[i]->is_static() || t < scenario.tags[i].start_s) continue;
      const Vec3 p = motion.tags[i]->pose_at(t).position;
      put(out, t, 6);
      out << ',' << scenario.tags[i].tag.name;
      for (double v : {p.x(), p.y(), p.z()}) {
        out << ',';
        put(out, v, 6);
      }
      out << '\n';
    }
  }
}

std::vector<CsvReading> read_readings_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot open readings file");
  std::string line;
  if (!std::getline(in, line)) throw InputError(path + ":1: empty readings file (expected the header)");
  const std::string seed_header = "time,posx,posy,posz,q1,q2,q3,q4,name,dist,phase,rssi";
  if (line.rfind(seed_header, 0) != 0)
    throw InputError(path + ":1: header must start with '" + seed_header + "'");
  std::vector<CsvReading> rows;
  int line_no = 1;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty()) continue;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    if (cells.size() < 12)
      throw InputError(path + ":" + std::to_string(line_no) + ": expected at least 12 columns, got " +
                       std::to_string(cells.size()));
    auto number = [&](size_t i) {
      char* end = nullptr;
      const double v = std::strtod(cells[i].c_str(), &end);
      if (cells[i].empty() || *end != '\0' || !std::isfinite(v))
        throw InputError(path + ":" + std::to_string(line_no) + ": column " + std::to_string(i + 1) +
                         " is not a finite number ('" + cells[i] + "')");
      return v;
    };
    CsvReading r;
    r.time_s = number(0);
    r.antenna_pose.position = Vec3(number(1), number(2), number(3));
    r.antenna_pose.orientation = Quat(number(7), number(4), number(5), number(6));
    r.tag = cells[8];
    r.distance_m = number(9);
    r.phase_rad = number(10);
    r.rssi = number(11);
    if (cells.size() > 12) r.antenna = cells[12];
    if (cells.size() > 13) r.frequency_hz = number(13);
    if (cells.size() > 14) r.channel = static_cast<int>(number(14));
    rows.push_back(std::move(r));
  }
  return rows;
}

}  // namespace rfidray::cli
