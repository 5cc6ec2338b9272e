#include "io/readings_csv.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <stdexcept>
#include <tuple>

#include "core/error.h"
#include "core/limits.h"
#include "core/units.h"

namespace rfidray::io {
namespace {

// Fixed-point text, correctly rounded (std::to_chars: same digits as printf "%.*f", several times faster);
// values that print as zero print as "0.…" (never "-0.…").
// A non-finite value is a bug upstream (inputs are range-checked where they enter): refuse to write it.
void put(std::ostream& out, double v, int decimals, const char* file, const char* column) {
  if (!std::isfinite(v))
    throw std::logic_error(std::string("internal error: ") + file + " column '" + column + "': non-finite value " +
                           (std::isnan(v) ? "nan" : v > 0 ? "inf" : "-inf") + " (not written)");
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

namespace {

// One row; the one place that fixes the columns' formatting.
void put_row(std::ostream& out, double time_s, const Pose& pose, const std::string& tag, double distance_m,
             double phase_rad, double rssi, const std::string& antenna, double frequency_hz, int hop_index) {
  const Vec3& p = pose.position;
  const Quat& q = pose.orientation;
  constexpr const char* kFile = "readings CSV";
  put(out, time_s, 6, kFile, "time");
  const char* pos_col[] = {"posx", "posy", "posz"};
  const char* quat_col[] = {"q1", "q2", "q3", "q4"};
  int k = 0;
  for (double v : {p.x(), p.y(), p.z()}) {
    out << ',';
    put(out, v, 6, kFile, pos_col[k++]);
  }
  k = 0;
  for (double v : {q.x(), q.y(), q.z(), q.w()}) {
    out << ',';
    put(out, v, 9, kFile, quat_col[k++]);
  }
  out << ',' << tag << ',';
  put(out, distance_m, 6, kFile, "dist");
  out << ',';
  put(out, phase_rad, 6, kFile, "phase");
  out << ',';
  put(out, rssi, 4, kFile, "rssi");
  out << ',' << antenna << ',';
  put(out, frequency_hz, 0, kFile, "frequency_hz");
  out << ',' << hop_index << '\n';
}

}  // namespace

void write_readings_rows(std::ostream& out, const Scenario& scenario, size_t antenna,
                         const std::vector<ReadRecord>& reads) {
  const std::string& name = scenario.antennas.at(antenna).reader.name;
  for (const ReadRecord& r : reads)
    put_row(out, r.time_s, r.antenna_pose, scenario.tags.at(r.tag).tag.name, r.distance_m, r.reading.phase_rad,
            r.reading.rssi_dbm, name, r.frequency_hz, r.hop_index);
}

void write_readings_csv(std::ostream& out, const std::vector<ReadingRow>& rows) {
  out << kReadingsHeader << '\n';
  for (const ReadingRow& r : rows)
    put_row(out, r.time_s, r.antenna_pose, r.tag, r.distance_m, r.phase_rad, r.rssi, r.antenna, r.frequency_hz,
            r.hop_index);
}

void write_tags_csv(std::ostream& out, const Scenario& scenario, const SceneMotion& motion) {
  out << "name,x,y,z\n";
  for (size_t i = 0; i < scenario.tags.size(); ++i) {
    const Vec3 p = motion.tags[i]->pose_at(0.0).position;
    out << scenario.tags[i].tag.name;
    const char* col[] = {"x", "y", "z"};
    int k = 0;
    for (double v : {p.x(), p.y(), p.z()}) {
      out << ',';
      put(out, v, 6, "tags.csv", col[k++]);
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
      put(out, t, 6, "tags_trajectory.csv", "time");
      out << ',' << scenario.tags[i].tag.name;
      const char* col[] = {"x", "y", "z"};
      int k = 0;
      for (double v : {p.x(), p.y(), p.z()}) {
        out << ',';
        put(out, v, 6, "tags_trajectory.csv", col[k++]);
      }
      out << '\n';
    }
  }
}


namespace {

std::string where(const std::filesystem::path& file, int line) {
  return file.string() + ":" + std::to_string(line) + ": ";
}

std::string trim(std::string s) {
  while (!s.empty() && (s.back() == '\r' || s.back() == ' ' || s.back() == '\t')) s.pop_back();
  size_t i = 0;
  while (i < s.size() && (s[i] == ' ' || s[i] == '\t')) ++i;
  return s.substr(i);
}

double parse_number(const std::string& text, const std::string& column, const std::filesystem::path& file, int line) {
  const std::string t = trim(text);
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), v);
  if (t.empty() || ec != std::errc() || ptr != t.data() + t.size())
    throw InputError(where(file, line) + "column '" + column + "': not a number ('" + t + "')");
  if (!std::isfinite(v)) throw InputError(where(file, line) + "column '" + column + "': not finite");
  return v;
}

// Calls row(fields, line) for every non-blank line after the header, each with exactly header_size fields.
template <typename Row>
void for_each_row(std::istream& in, const std::filesystem::path& file, size_t header_size, Row&& row) {
  std::string text;
  int line = 1;
  while (std::getline(in, text)) {
    ++line;
    if (trim(text).empty()) continue;
    const std::vector<std::string> f = split_csv_line(text);
    if (f.size() != header_size)
      throw InputError(where(file, line) + "expected " + std::to_string(header_size) + " fields, got " +
                       std::to_string(f.size()));
    row(f, line);
  }
}

}  // namespace

std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> out;
  std::string field;
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') field += '"', ++i;
      else if (c == '"') quoted = false;
      else field += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      out.push_back(field);
      field.clear();
    } else if (c != '\r') {
      field += c;
    }
  }
  out.push_back(field);
  return out;
}

std::vector<ReadingRow> read_readings_csv(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": cannot open readings file");
  static const std::vector<std::string> kRequired{"time", "posx", "posy", "posz", "q1", "q2",
                                                  "q3",   "q4",   "name", "dist", "phase", "rssi"};
  std::string text;
  if (!std::getline(in, text)) throw InputError(file.string() + ": empty file (expected a header line)");
  std::vector<std::string> header = split_csv_line(text);
  for (auto& h : header) h = trim(h);
  for (size_t i = 0; i < kRequired.size(); ++i)
    if (i >= header.size() || header[i] != kRequired[i])
      throw InputError(where(file, 1) + "header column " + std::to_string(i + 1) + " must be '" + kRequired[i] +
                       "' (header must start with time,posx,posy,posz,q1,q2,q3,q4,name,dist,phase,rssi)");
  int col_antenna = -1, col_hop = -1, col_frequency = -1;
  for (size_t i = kRequired.size(); i < header.size(); ++i) {
    if (header[i] == "antenna") col_antenna = static_cast<int>(i);
    else if (header[i] == "channel") col_hop = static_cast<int>(i);
    else if (header[i] == "frequency_hz" || header[i] == "frequency") col_frequency = static_cast<int>(i);
  }
  std::vector<ReadingRow> rows;
  for_each_row(in, file, header.size(), [&](const std::vector<std::string>& f, int line) {
    ReadingRow r;
    r.line = line;
    auto num = [&](int i) { return parse_number(f[i], header[i], file, line); };
    r.time_s = num(0);
    r.antenna_pose.position = Vec3(num(1), num(2), num(3));
    for (int k = 0; k < 3; ++k)
      if (std::abs(r.antenna_pose.position[k]) > limits::kMaxCoordinateM)
        throw InputError(where(file, line) + "column '" + header[1 + k] + "': " + trim(f[1 + k]) +
                         " m is outside ±1e8 m (core/limits.h)");
    const Eigen::Vector4d q(num(4), num(5), num(6), num(7));
    if (q.norm() < 1e-9) throw InputError(where(file, line) + "quaternion q1..q4 has zero norm");
    r.antenna_pose.orientation = Quat(q[3], q[0], q[1], q[2]).normalized();
    r.tag = trim(f[8]);
    if (r.tag.empty()) throw InputError(where(file, line) + "column 'name': empty tag name");
    r.distance_m = num(9);
    r.phase_rad = num(10);
    if (r.phase_rad < -kPi - 1e-6 || r.phase_rad > kTwoPi + 1e-6)
      throw InputError(where(file, line) + "column 'phase': " + trim(f[10]) +
                       " rad is outside [-pi, 2pi) (expected radians in [0, 2pi) or (-pi, pi])");
    r.rssi = num(11);
    if (col_antenna >= 0) r.antenna = trim(f[col_antenna]);
    if (col_hop >= 0) {
      const double hop = num(col_hop);
      if (hop < 0.0 || hop != std::floor(hop) || hop > 1e6)
        throw InputError(where(file, line) + "column 'channel': hop index must be a whole number >= 0 (got '" +
                         trim(f[col_hop]) + "')");
      r.hop_index = static_cast<int>(hop);
    }
    if (col_frequency >= 0) {
      r.frequency_hz = num(col_frequency);
      if (r.frequency_hz <= 0.0) throw InputError(where(file, line) + "column '" + header[col_frequency] + "': must be > 0");
    }
    rows.push_back(std::move(r));
  });
  return rows;
}

std::map<std::string, Vec3> read_truth_csv(const std::filesystem::path& file) {
  std::ifstream in(file);
  if (!in) throw InputError(file.string() + ": cannot open truth file");
  std::string text;
  if (!std::getline(in, text)) throw InputError(file.string() + ": empty file (expected header name,x,y,z)");
  std::vector<std::string> header = split_csv_line(text);
  for (auto& h : header) h = trim(h);
  if (header.size() < 4 || header[0] != "name" || header[1] != "x" || header[2] != "y" || header[3] != "z")
    throw InputError(where(file, 1) + "header must start with name,x,y,z");
  std::map<std::string, Vec3> out;
  for_each_row(in, file, header.size(), [&](const std::vector<std::string>& f, int line) {
    const std::string name = trim(f[0]);
    if (name.empty()) throw InputError(where(file, line) + "column 'name': empty tag name");
    const Vec3 p(parse_number(f[1], "x", file, line), parse_number(f[2], "y", file, line),
                 parse_number(f[3], "z", file, line));
    for (int k = 0; k < 3; ++k)
      if (std::abs(p[k]) > limits::kMaxCoordinateM)
        throw InputError(where(file, line) + "column '" + header[1 + k] + "': " + trim(f[1 + k]) +
                         " m is outside ±1e8 m (core/limits.h)");
    if (!out.emplace(name, p).second) throw InputError(where(file, line) + "duplicate tag '" + name + "'");
  });
  return out;
}

std::vector<loc::TagReads> group_by_tag(const std::vector<std::vector<ReadingRow>>& files, double default_frequency_hz) {
  using Key = std::tuple<std::string, size_t, std::string, int, double>;
  std::map<Key, loc::ReadGroup> groups;
  for (size_t fi = 0; fi < files.size(); ++fi)
    for (const ReadingRow& r : files[fi]) {
      const double f = r.frequency_hz > 0.0 ? r.frequency_hz : default_frequency_hz;
      loc::ReadGroup& g = groups[Key{r.tag, fi, r.antenna, r.hop_index, f}];
      if (g.reads.empty()) {
        g.antenna = "file" + std::to_string(fi) + (r.antenna.empty() ? "" : ":" + r.antenna) +
                    (r.hop_index < 0 ? "" : "/" + std::to_string(r.hop_index));
        g.frequency_hz = f;
      }
      // The truth column `dist` is deliberately not copied.
      g.reads.push_back(loc::PhaseRead{r.time_s, r.antenna_pose.position, r.antenna_pose.orientation, r.phase_rad});
    }
  std::vector<loc::TagReads> out;
  for (auto& [key, g] : groups) {
    std::stable_sort(g.reads.begin(), g.reads.end(),
                     [](const loc::PhaseRead& a, const loc::PhaseRead& b) { return a.time_s < b.time_s; });
    const std::string& name = std::get<0>(key);
    if (out.empty() || out.back().tag != name) out.push_back(loc::TagReads{name, {}});
    out.back().groups.push_back(std::move(g));
  }
  return out;
}

}  // namespace rfidray::io
