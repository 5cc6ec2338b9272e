#include "io/real_log.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <regex>
#include <set>

#include "core/error.h"
#include "core/units.h"
#include "io/checked_yaml.h"
#include "io/csv_fields.h"
#include "core/number_text.h"

namespace rfidray::io {

namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------------------------
// Fields, layouts and their usual column names
// ---------------------------------------------------------------------------------------------------------------

enum Field { kEpc, kPhase, kFrequency, kChannel, kRssi, kTime, kAntenna, kX, kY, kZ, kQx, kQy, kQz, kQw, kFieldCount };
constexpr std::array<const char*, kFieldCount> kFieldKeys = {"epc", "phase", "frequency", "channel", "rssi",
                                                             "time", "antenna", "x", "y", "z", "qx", "qy", "qz", "qw"};

FieldSource& field_of(ColumnMap& m, Field f) {
  FieldSource* all[kFieldCount] = {&m.epc, &m.phase, &m.frequency, &m.channel, &m.rssi, &m.time, &m.antenna,
                                   &m.x,   &m.y,     &m.z,         &m.qx,      &m.qy,   &m.qz,   &m.qw};
  return *all[f];
}
const FieldSource& field_of(const ColumnMap& m, Field f) { return field_of(const_cast<ColumnMap&>(m), f); }

// Normalized names (csv_fields.h: normalized_name) tried in order, per layout and field.
using Names = std::array<std::vector<const char*>, kFieldCount>;

const Names& names_of(LogLayout layout) {
  // Position columns are rare in reader logs; when present they are used in every layout.
  static const std::vector<const char*> x{"x", "posx", "antennax"}, y{"y", "posy", "antennay"},
      z{"z", "posz", "antennaz"}, qx{"qx"}, qy{"qy"}, qz{"qz"}, qw{"qw"};
  static const Names octane{{
      {"epc", "epc96", "epcdata", "epchex"},
      {"phaseangleinradians", "phaseangleinrad", "phaseanglerad", "phaseangleindegrees", "phaseangleindeg",
       "phaseangledeg", "phaseangledegrees", "phaseangle", "rfphaseangle", "phaserad", "phasedeg", "phase"},
      {"channelinmhz", "frequencyinmhz", "frequencymhz", "frequencykhz", "frequencyhz", "frequency", "freq",
       "freqmhz"},
      {"channelindex", "channel"},
      {"peakrssiindbm", "peakrssidbm", "peakrssi", "rssi", "rssidbm"},
      {"firstseentime", "firstseentimeutc", "lastseentime", "lastseentimeutc", "timestamp", "time"},
      {"antennaportnumber", "antennaport", "antenna", "antennaid", "port"},
      x, y, z, qx, qy, qz, qw}};
  static const Names sllurp{{
      {"epc96", "epc", "epcdata"},
      {"impinjrfphaseangle", "impinjphase", "phaseangle", "phase"},
      {"frequency", "frequencyhz", "frequencymhz"},
      {"channelindex", "channel"},
      {"impinjpeakrssi", "peakrssi", "rssi"},
      {"firstseentimestamputc", "lastseentimestamputc", "timestampus", "timestamp", "time"},
      {"antennaid", "antenna"},
      x, y, z, qx, qy, qz, qw}};
  static const Names per_stop{{{"epc"}, {"phase"}, {"frequency"}, {}, {"rssi"}, {"time"}, {"antennaindex"},
                               {"x"}, {"y"}, {"z"}, qx, qy, qz, qw}};
  static const Names columns{{{}, {}, {}, {}, {}, {}, {}, x, y, z, qx, qy, qz, qw}};
  switch (layout) {
    case LogLayout::kOctane: return octane;
    case LogLayout::kSllurp: return sllurp;
    case LogLayout::kPerStop: return per_stop;
    default: return columns;
  }
}

// The unit a layout assumes when neither the column map nor the name says.
LogUnit layout_unit(LogLayout layout, Field f) {
  switch (f) {
    case kPhase: return layout == LogLayout::kSllurp ? LogUnit::kImpinj12Bit : LogUnit::kRad;
    case kFrequency: return layout == LogLayout::kPerStop ? LogUnit::kHz : LogUnit::kAuto;
    case kTime: return layout == LogLayout::kPerStop ? LogUnit::kS : LogUnit::kAuto;
    case kRssi: return LogUnit::kDbm;
    default: return LogUnit::kAuto;
  }
}

bool ends_with(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}
bool contains(const std::string& s, const char* part) { return s.find(part) != std::string::npos; }

// The unit a column's name states, kAuto if none.
LogUnit unit_from_name(Field f, const std::string& raw) {
  const std::string n = normalized_name(raw);
  std::string lower;
  for (char c : raw) lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  lower = trim(lower);
  switch (f) {
    case kPhase:
      if (contains(n, "deg")) return LogUnit::kDeg;
      if (contains(n, "rad")) return LogUnit::kRad;
      if (n.rfind("impinj", 0) == 0) return LogUnit::kImpinj12Bit;
      return LogUnit::kAuto;
    case kFrequency:
      if (contains(n, "mhz")) return LogUnit::kMhz;
      if (contains(n, "khz")) return LogUnit::kKhz;
      if (ends_with(n, "hz")) return LogUnit::kHz;
      return LogUnit::kAuto;
    case kTime:
      // Octane FirstSeenTime/LastSeenTime(.Utc) and LLRP …SeenTimestampUTC count µs since 1970.
      if (contains(n, "seentime")) return LogUnit::kUs;
      if (contains(n, "usec") || contains(n, "micro") || ends_with(n, "us") || contains(lower, "µs")) return LogUnit::kUs;
      if (contains(n, "msec") || contains(n, "milli") || ends_with(n, "ms")) return LogUnit::kMs;
      if (contains(n, "nsec") || contains(n, "nano") || ends_with(n, "ns")) return LogUnit::kNs;
      if (ends_with(n, "sec") || ends_with(n, "seconds") || ends_with(lower, "_s") || ends_with(lower, "(s)") ||
          ends_with(lower, "[s]"))
        return LogUnit::kS;
      return LogUnit::kAuto;
    case kRssi:
      if (n == "impinjpeakrssi" || contains(n, "cdbm") || contains(n, "centidbm")) return LogUnit::kCentiDbm;
      if (contains(n, "dbm")) return LogUnit::kDbm;
      return LogUnit::kAuto;
    default: return LogUnit::kAuto;
  }
}

const char* unit_name(LogUnit u) {
  switch (u) {
    case LogUnit::kRad: return "rad";
    case LogUnit::kDeg: return "deg";
    case LogUnit::kImpinj12Bit: return "impinj (2pi/4096)";
    case LogUnit::kHz: return "Hz";
    case LogUnit::kKhz: return "kHz";
    case LogUnit::kMhz: return "MHz";
    case LogUnit::kS: return "s";
    case LogUnit::kMs: return "ms";
    case LogUnit::kUs: return "us";
    case LogUnit::kNs: return "ns";
    case LogUnit::kDbm: return "dBm";
    case LogUnit::kCentiDbm: return "1/100 dBm";
    default: return "auto";
  }
}

// ---------------------------------------------------------------------------------------------------------------
// Tables: a CSV or JSON-lines file as header + rows of text fields
// ---------------------------------------------------------------------------------------------------------------

struct Table {
  std::string file;
  int header_line = 0;
  std::vector<std::string> header;  // as written
  struct Row {
    int line = 0;
    std::vector<std::string> fields;
  };
  std::vector<Row> rows;
  bool json = false;
};

bool is_comment(const std::string& t) { return t.rfind("//", 0) == 0 || t.rfind("#", 0) == 0; }
std::string comment_text(const std::string& t) { return trim(t.substr(t[0] == '#' ? 1 : 2)); }

// "2024-07-02T11:32:44.6458200+03:00", "2025-05-06 10:00:05.123456", "…Z": seconds since 1970 UTC (no offset:
// UTC). nullopt when the text is not of that shape.
std::optional<double> parse_iso8601(const std::string& text) {
  static const std::regex re(
      R"(^(\d{4})-(\d{2})-(\d{2})[T ](\d{2}):(\d{2}):(\d{2})(\.\d+)?\s*(Z|[+-]\d{2}:?\d{2})?$)");
  std::smatch m;
  if (!std::regex_match(text, m, re)) return std::nullopt;
  const int y = std::stoi(m[1]), mo = std::stoi(m[2]), d = std::stoi(m[3]);
  const int h = std::stoi(m[4]), mi = std::stoi(m[5]), s = std::stoi(m[6]);
  if (mo < 1 || mo > 12 || d < 1 || d > 31 || h > 23 || mi > 59 || s > 60) return std::nullopt;
  // Days from 1970-01-01 of a proleptic Gregorian date (H. Hinnant's days_from_civil).
  const int yy = y - (mo <= 2 ? 1 : 0);
  const int era = (yy >= 0 ? yy : yy - 399) / 400;
  const int yoe = yy - era * 400;
  const int doy = (153 * (mo + (mo > 2 ? -3 : 9)) + 2) / 5 + d - 1;
  const int doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
  const long long days = static_cast<long long>(era) * 146097 + doe - 719468;
  double t = static_cast<double>(days) * 86400.0 + h * 3600.0 + mi * 60.0 + s;
  if (m[7].matched) t += std::stod("0" + m[7].str());
  if (m[8].matched && m[8].str() != "Z") {
    const std::string z = m[8].str();
    const int oh = std::stoi(z.substr(1, 2)), om = std::stoi(z.substr(z.size() - 2));
    const int sign = z[0] == '-' ? -1 : 1;
    t -= sign * (oh * 3600.0 + om * 60.0);  // local = UTC + offset
  }
  return t;
}

bool looks_like_data(const std::vector<std::string>& fields) {
  for (const std::string& f : fields)
    if (to_number(f) || parse_iso8601(trim(f))) return true;
  return false;
}

// Python literal (`sllurp inventory` prints tag dicts with repr) → JSON: quotes, b'' prefixes, True/False/None,
// tuples, trailing commas. Strings keep their content; \x escapes become \u00.
std::string python_to_json(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    const bool prefix = (c == 'b' || c == 'u' || c == 'r') && i + 1 < s.size() && (s[i + 1] == '\'' || s[i + 1] == '"') &&
                        (i == 0 || !std::isalnum(static_cast<unsigned char>(s[i - 1])));
    if (prefix) continue;
    if (c == '\'' || c == '"') {
      out += '"';
      for (++i; i < s.size() && s[i] != c; ++i) {
        if (s[i] == '\\' && i + 1 < s.size()) {
          if (s[i + 1] == 'x') out += "\\u00", ++i;
          else if (s[i + 1] == '\'') out += '\'', ++i;
          else out += s[i], out += s[++i];
        } else if (s[i] == '"') {
          out += "\\\"";
        } else {
          out += s[i];
        }
      }
      out += '"';
      continue;
    }
    if (std::isalpha(static_cast<unsigned char>(c))) {
      size_t j = i;
      while (j < s.size() && (std::isalnum(static_cast<unsigned char>(s[j])) || s[j] == '_')) ++j;
      const std::string word = s.substr(i, j - i);
      out += word == "True" ? "true" : word == "False" ? "false" : word == "None" ? "null" : word;
      i = j - 1;
      continue;
    }
    if (c == ')' || c == ']' || c == '}') {
      // Python allows a trailing comma ((2,) is a 1-tuple); JSON does not.
      size_t e = out.size();
      while (e > 0 && out[e - 1] == ' ') --e;
      if (e > 0 && out[e - 1] == ',') out.erase(e - 1);
    }
    out += c == '(' ? '[' : c == ')' ? ']' : c;
  }
  return out;
}

std::string json_text(const nlohmann::json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return v.get<std::string>();
  if (v.is_boolean()) return v.get<bool>() ? "1" : "0";
  if (v.is_array() && v.size() == 1) return json_text(v[0]);  // older sllurp: [value]
  return v.dump();
}

// The tag reports in one parsed line: an object, a list of them, or an RO_ACCESS_REPORT message.
void collect_reports(const nlohmann::json& j, std::vector<const nlohmann::json*>& out) {
  if (j.is_array()) {
    for (const auto& e : j) collect_reports(e, out);
    return;
  }
  if (!j.is_object()) return;
  if (j.contains("RO_ACCESS_REPORT")) return collect_reports(j["RO_ACCESS_REPORT"], out);
  if (j.contains("TagReportData")) return collect_reports(j["TagReportData"], out);
  out.push_back(&j);
}

Table read_json_lines(const fs::path& path, std::istream& in) {
  Table t;
  t.file = path.string();
  t.json = true;
  std::map<std::string, size_t> column;  // key → index in header
  std::vector<std::pair<int, std::vector<std::pair<size_t, std::string>>>> rows;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    if (line == 1) strip_bom(text);
    const std::string s = trim(text);
    if (s.empty() || is_comment(s)) continue;
    nlohmann::json j;
    try {
      j = nlohmann::json::parse(s);
    } catch (const nlohmann::json::exception& e) {
      try {
        j = nlohmann::json::parse(python_to_json(s));
      } catch (const nlohmann::json::exception&) {
        throw InputError(located(t.file, line) + "not a JSON object (" + e.what() + ")");
      }
    }
    std::vector<const nlohmann::json*> reports;
    collect_reports(j, reports);
    if (reports.empty()) throw InputError(located(t.file, line) + "no tag report in this line (expected a JSON object)");
    for (const nlohmann::json* r : reports) {
      std::vector<std::pair<size_t, std::string>> fields;
      auto add = [&](const std::string& key, const nlohmann::json& v) {
        auto [it, fresh] = column.emplace(key, t.header.size());
        if (fresh) t.header.push_back(key);
        fields.emplace_back(it->second, json_text(v));
      };
      for (auto it = r->begin(); it != r->end(); ++it) {
        if (it->is_object()) {  // EPCData: {EPC: …} and other one-level groups
          for (auto in_it = it->begin(); in_it != it->end(); ++in_it)
            if (!r->contains(in_it.key())) add(in_it.key(), in_it.value());
        } else {
          add(it.key(), it.value());
        }
      }
      rows.emplace_back(line, std::move(fields));
    }
  }
  if (rows.empty()) throw InputError(t.file + ": empty file (no tag reports)");
  for (auto& [l, fields] : rows) {
    Table::Row row{l, std::vector<std::string>(t.header.size())};
    for (auto& [i, v] : fields) row.fields[i] = std::move(v);
    t.rows.push_back(std::move(row));
  }
  return t;
}

// A CSV file: the header is the first line that is not a comment (// or #), unless that line already holds data
// (a number or a time in some field) — then it is the last comment line before it (ItemTest).
Table read_csv_table(const fs::path& path, std::istream& in, bool allow_no_rows) {
  Table t;
  t.file = path.string();
  std::string text, last_comment;
  int line = 0, last_comment_line = 0;
  bool have_header = false;
  while (std::getline(in, text)) {
    ++line;
    if (line == 1) strip_bom(text);
    const std::string s = trim(text);
    if (s.empty()) continue;
    if (!have_header) {
      if (is_comment(s)) {
        last_comment = comment_text(s);
        last_comment_line = line;
        continue;
      }
      std::vector<std::string> fields = split_csv_line(text);
      if (looks_like_data(fields)) {
        if (last_comment.empty())
          throw InputError(located(t.file, line) + "no header line (the first line holds data; expected column names)");
        t.header = split_csv_line(last_comment);
        t.header_line = last_comment_line;
      } else {
        t.header = std::move(fields);
        t.header_line = line;
        have_header = true;
        continue;
      }
      have_header = true;
    }
    if (is_comment(s)) continue;
    std::vector<std::string> fields = split_csv_line(text);
    if (fields.size() != t.header.size())
      throw InputError(located(t.file, line) + "expected " + std::to_string(t.header.size()) +
                       " fields (as the header on line " + std::to_string(t.header_line) + "), got " +
                       std::to_string(fields.size()));
    t.rows.push_back(Table::Row{line, std::move(fields)});
  }
  for (std::string& h : t.header) h = trim(h);
  if (!have_header) throw InputError(t.file + ": empty file (expected a header line and reads)");
  if (t.rows.empty() && !allow_no_rows) throw InputError(t.file + ": empty file (a header but no reads)");
  return t;
}

bool starts_with_json(const fs::path& path) {
  std::ifstream in(path);
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    if (++line == 1) strip_bom(text);
    const std::string s = trim(text);
    if (s.empty() || is_comment(s)) continue;
    return s[0] == '{' || s[0] == '[';
  }
  return false;
}

Table read_table(const fs::path& path, bool allow_no_rows = false) {
  if (!fs::exists(path)) throw InputError(path.string() + ": no such file");
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot open log file");
  if (starts_with_json(path)) return read_json_lines(path, in);
  return read_csv_table(path, in, allow_no_rows);
}

// ---------------------------------------------------------------------------------------------------------------
// Resolving fields against a header, and converting rows
// ---------------------------------------------------------------------------------------------------------------

struct Column {
  int index = -1;
  std::optional<double> constant;
  std::string name;  // for messages: the header's spelling, or the key for constants
  LogUnit unit = LogUnit::kAuto;
  bool present() const { return index >= 0 || constant.has_value(); }
};

struct Resolved {
  std::array<Column, kFieldCount> f;  // the first column found per field
  // Every column found per field, in the layout's order: a row whose first column is empty (a JSON report
  // without that key) uses the next (ImpinjPhase where ImpinjRFPhaseAngle is missing).
  std::array<std::vector<Column>, kFieldCount> alts;

  const Column& pick(Field f, const std::vector<std::string>& fields) const {
    for (const Column& c : alts[f])
      if (c.constant || !trim(fields[c.index]).empty()) return c;
    return this->f[f];
  }
};

std::string header_list(const Table& t) {
  std::string s;
  for (const std::string& h : t.header) s += (s.empty() ? "" : ", ") + h;
  return s;
}

Resolved resolve(const Table& t, LogLayout layout, const ColumnMap& user, std::vector<std::string>& notes) {
  std::vector<std::string> norm;
  for (const std::string& h : t.header) norm.push_back(normalized_name(h));
  auto find = [&](const std::string& n) {
    const auto it = std::find(norm.begin(), norm.end(), n);
    return it == norm.end() ? -1 : static_cast<int>(it - norm.begin());
  };
  Resolved r;
  const Names& names = names_of(layout);
  for (int f = 0; f < kFieldCount; ++f) {
    Column& c = r.f[f];
    const FieldSource& src = field_of(user, static_cast<Field>(f));
    if (src.constant) {
      c.constant = src.constant;
      c.name = kFieldKeys[f];
    } else if (!src.column.empty()) {
      c.index = find(normalized_name(src.column));
      if (c.index < 0)
        throw InputError(located(t.file, t.header_line) + "column '" + src.column + "' (--columns " + kFieldKeys[f] +
                         "=" + src.column + "): not in the header (" + header_list(t) + ")");
    } else {
      for (const char* n : names[f]) {
        Column alt;
        if ((alt.index = find(n)) < 0) continue;
        alt.name = t.header[alt.index];
        r.alts[f].push_back(alt);
      }
      if (!r.alts[f].empty()) c = r.alts[f].front();
    }
    if (c.index >= 0) c.name = t.header[c.index];
    if (r.alts[f].empty() && c.present()) r.alts[f].push_back(c);
  }
  // Units: the column map, then the name, then the layout.
  const std::pair<Field, LogUnit> explicit_units[] = {{kPhase, user.phase_unit}, {kFrequency, user.frequency_unit},
                                                     {kTime, user.time_unit}, {kRssi, user.rssi_unit}};
  for (const auto& fu : explicit_units) {
    const Field f = fu.first;  // not a structured binding: clang 14 cannot capture those in the lambda below
    const LogUnit u = fu.second;
    for (Column* c : [&] {
           std::vector<Column*> all{&r.f[f]};
           for (Column& a : r.alts[f]) all.push_back(&a);
           return all;
         }()) {
      if (!c->present()) continue;
      c->unit = u != LogUnit::kAuto ? u : c->index >= 0 ? unit_from_name(f, c->name) : LogUnit::kAuto;
      if (c->unit == LogUnit::kAuto) c->unit = layout_unit(layout, f);
    }
  }
  if (r.f[kPhase].constant) throw InputError("--columns: phase must be a column, not a constant");
  // Missing essentials, reported at the header.
  const std::string at = located(t.file, t.header_line);
  if (!r.f[kEpc].present())
    throw InputError(at + "column 'epc': no EPC column (header: " + header_list(t) + "); name it with --columns epc=NAME");
  if (!r.f[kPhase].present())
    throw InputError(at + "column 'phase': no phase column (header: " + header_list(t) +
                     "); the reader must report phase (Impinj: enable the RF phase angle), or name it with "
                     "--columns phase=NAME");
  if (!r.f[kRssi].present())
    throw InputError(at + "column 'rssi': no RSSI column (header: " + header_list(t) + "); name it with --columns rssi=NAME");
  const int pos = r.f[kX].present() + r.f[kY].present() + r.f[kZ].present();
  if (pos != 0 && pos != 3)
    throw InputError(at + "column 'x','y','z': give all three antenna position columns or none");
  const int quat = r.f[kQx].present() + r.f[kQy].present() + r.f[kQz].present() + r.f[kQw].present();
  if (quat != 0 && quat != 4)
    throw InputError(at + "column 'qx'..'qw': give all four antenna quaternion columns or none");
  if (quat == 4 && pos == 0) throw InputError(at + "column 'qx'..'qw': quaternion columns without x,y,z");
  std::string used;
  for (int f = 0; f < kFieldCount; ++f) {
    const Column& c = r.f[f];
    if (!c.present()) continue;
    used += std::string(used.empty() ? "" : ", ") + kFieldKeys[f] + "=" +
            (c.constant ? num(*c.constant) : "'" + c.name + "'");
    if (c.unit != LogUnit::kAuto && (f == kPhase || f == kFrequency || f == kTime))
      used += std::string(" [") + unit_name(c.unit) + "]";
  }
  notes.push_back(t.file + ": columns " + used);
  return r;
}

// Magnitude classes of values whose unit is guessed: every row must fall in the class of the first one.
struct MagnitudeClass {
  int cls = -1;
  std::string first;  // "FILE:LINE" of the row that set it
};

struct Converter {
  const RealLogOptions& options;
  MagnitudeClass frequency_class, time_class;
  std::vector<std::string>& notes;
  bool noted_iso_utc = false;

  double number(const Table& t, const Column& c, const Table::Row& row) const {
    if (c.constant) return *c.constant;
    return parse_finite(row.fields[c.index], t.file, row.line, c.name);
  }

  double phase(const Table& t, const Column& c, const Table::Row& row) const {
    const double v = number(t, c, row);
    const std::string at = located(t.file, row.line) + "column '" + c.name + "': ";
    double rad = 0.0;
    switch (c.unit) {
      case LogUnit::kDeg:
        if (v > 360.0 + 1e-9 || v < -180.0 - 1e-9)
          throw InputError(at + num(v) + " is outside [-180, 360] degrees (mixed units?)");
        rad = v * (kPi / 180.0);
        break;
      case LogUnit::kImpinj12Bit:
        if (v != std::floor(v) || v < 0.0 || v > 4095.0)
          throw InputError(at + num(v) + " is not a 12-bit phase (a whole number 0..4095 in 2pi/4096 steps)" +
                           (v >= 0.0 && v <= kTwoPi + 1e-6 ? "; if it is in radians, give --columns phase_unit=rad" : ""));
        rad = v * (kTwoPi / 4096.0);
        break;
      default:
        // Readers report [0, 2π) (some print 2π itself after rounding) or (−π, π].
        if (v > kTwoPi + 1e-6)
          throw InputError(at + num(v) + " is above 2pi but the phase is taken as radians (mixed units? for degrees "
                                         "give --columns phase_unit=deg)");
        if (v < -kPi - 1e-6) throw InputError(at + num(v) + " rad is below -pi (expected [0, 2pi) or (-pi, pi])");
        rad = v >= kTwoPi ? 0.0 : v;  // 2π printed with rounding is 0
    }
    if (options.negate_phase) rad = -rad;
    return wrap_to_2pi(rad);
  }

  double frequency_hz(const Table& t, const Column& c, const Table::Row& row) {
    const double v = number(t, c, row);
    const std::string where = located(t.file, row.line);
    LogUnit unit = c.unit;
    if (unit == LogUnit::kAuto) {
      unit = std::abs(v) < 1e4 ? LogUnit::kMhz : std::abs(v) < 1e7 ? LogUnit::kKhz : LogUnit::kHz;
      const int cls = static_cast<int>(unit);
      if (frequency_class.cls < 0) {
        frequency_class = {cls, t.file + ":" + std::to_string(row.line)};
        notes.push_back(t.file + ": column '" + c.name + "' read as " + unit_name(unit) + " (by magnitude)");
      } else if (frequency_class.cls != cls) {
        throw InputError(where + "column '" + c.name + "': " + num(v) + " looks like " + unit_name(unit) +
                         " but earlier values (" + frequency_class.first + ") like " +
                         unit_name(static_cast<LogUnit>(frequency_class.cls)) +
                         " (mixed units; give --columns frequency_unit=hz|khz|mhz)");
      }
    }
    const double hz = unit == LogUnit::kMhz ? v * 1e6 : unit == LogUnit::kKhz ? v * 1e3 : v;
    if (hz < 1e8 || hz > 1e10)
      throw InputError(where + "column '" + c.name + "': " + num(v) + " " + unit_name(unit) + " = " + num(hz) +
                       " Hz is not a UHF carrier (100 MHz .. 10 GHz): wrong unit?");
    return hz;
  }

  double channel_frequency_hz(const Table& t, const Column& c, const Table::Row& row) const {
    const double v = number(t, c, row);
    const std::string at = located(t.file, row.line) + "column '" + c.name + "': ";
    const auto& plan = options.channel_plan_hz;
    if (v != std::floor(v) || v < 1.0)
      throw InputError(at + "channel index " + num(v) + " is not a whole number >= 1 (LLRP channel indices start at 1)");
    if (v > static_cast<double>(plan.size()))
      throw InputError(at + "channel index " + num(v) + " is beyond the channel plan (" + std::to_string(plan.size()) +
                       " channels)");
    return plan[static_cast<size_t>(v) - 1];
  }

  double time_s(const Table& t, const Column& c, const Table::Row& row) {
    const std::string where = located(t.file, row.line);
    if (c.index >= 0) {
      const std::string text = trim(row.fields[c.index]);
      if (const auto iso = parse_iso8601(text)) {
        if (!noted_iso_utc) {
          noted_iso_utc = true;
          notes.push_back(t.file + ": column '" + c.name + "' holds ISO 8601 times, read as seconds since 1970 UTC" +
                          (text.back() == 'Z' || std::regex_search(text, std::regex("[+-]\\d{2}:?\\d{2}$"))
                               ? ""
                               : " (no UTC offset given: taken as UTC)"));
        }
        return *iso;
      }
    }
    const double v = number(t, c, row);
    LogUnit unit = c.unit;
    if (unit == LogUnit::kAuto) {
      // Epoch clocks by magnitude (2001 onwards): ≥ 1e17 ns, ≥ 1e14 µs, ≥ 1e11 ms; smaller values are seconds.
      const double a = std::abs(v);
      unit = a >= 1e17 ? LogUnit::kNs : a >= 1e14 ? LogUnit::kUs : a >= 1e11 ? LogUnit::kMs : LogUnit::kS;
      const int cls = static_cast<int>(unit);
      if (time_class.cls < 0) {
        time_class = {cls, t.file + ":" + std::to_string(row.line)};
        notes.push_back(t.file + ": column '" + c.name + "' read as " + unit_name(unit) + " (by magnitude)");
      } else if (time_class.cls != cls && v != 0.0) {
        throw InputError(where + "column '" + c.name + "': " + num(v) + " looks like " + unit_name(unit) +
                         " but earlier values (" + time_class.first + ") like " +
                         unit_name(static_cast<LogUnit>(time_class.cls)) +
                         " (mixed units; give --columns time_unit=s|ms|us|ns)");
      }
    }
    switch (unit) {
      case LogUnit::kMs: return v * 1e-3;
      case LogUnit::kUs: return v * 1e-6;
      case LogUnit::kNs: return v * 1e-9;
      default: return v;
    }
  }

  static std::string epc(const Table& t, const Column& c, const Table::Row& row) {
    std::string s = trim(row.fields[c.index]);
    // Python bytes printed by sllurp scripts: b'3034…'
    if (s.size() >= 3 && (s.rfind("b'", 0) == 0 || s.rfind("b\"", 0) == 0) && (s.back() == '\'' || s.back() == '"'))
      s = s.substr(2, s.size() - 3);
    s.erase(std::remove(s.begin(), s.end(), ' '), s.end());  // Octane's Epc.ToString() groups by words
    const std::string at = located(t.file, row.line) + "column '" + c.name + "': ";
    if (s.empty()) throw InputError(at + "empty EPC");
    if (s.find_first_of(",\"\n") != std::string::npos) throw InputError(at + "EPC '" + s + "' holds a comma or quote");
    return s;
  }

  static std::string antenna(const Table& t, const Column& c, const Table::Row& row) {
    const std::string s = c.constant ? num(*c.constant) : trim(row.fields[c.index]);
    const std::optional<double> port = to_number(s);
    if (port && *port == std::floor(*port) && *port >= 0 && *port < 1e6)
      return "port" + std::to_string(static_cast<long long>(*port));
    const std::string at = located(t.file, row.line) + "column '" + c.name + "': ";
    if (s.empty()) throw InputError(at + "empty antenna");
    if (s.find_first_of(",\"\n") != std::string::npos) throw InputError(at + "antenna '" + s + "' holds a comma or quote");
    return s;
  }

  // One read; with_time = false leaves time_s at 0 (per-stop decides it afterwards).
  RealRead read(const Table& t, const Resolved& r, const Table::Row& row, bool with_time) {
    RealRead out;
    out.file = t.file;
    out.line = row.line;
    const std::vector<std::string>& fields = row.fields;
    out.epc = epc(t, r.pick(kEpc, fields), row);
    out.phase_rad = phase(t, r.pick(kPhase, fields), row);
    const Column& rssi_column = r.pick(kRssi, fields);
    const double rssi = number(t, rssi_column, row);
    out.rssi_dbm = rssi_column.unit == LogUnit::kCentiDbm ? rssi / 100.0 : rssi;
    if (out.rssi_dbm < -200.0 || out.rssi_dbm > 100.0)
      throw InputError(located(t.file, row.line) + "column '" + rssi_column.name + "': " + num(rssi) +
                       " is not an RSSI in dBm (Impinj's 1/100 dBm? give --columns rssi_unit=cdbm)");
    if (r.f[kFrequency].present()) out.frequency_hz = frequency_hz(t, r.pick(kFrequency, fields), row);
    else if (r.f[kChannel].present()) out.frequency_hz = channel_frequency_hz(t, r.pick(kChannel, fields), row);
    else out.frequency_hz = options.default_frequency_hz;
    if (with_time) out.time_s = time_s(t, r.pick(kTime, fields), row);
    if (r.f[kAntenna].present()) out.antenna = antenna(t, r.pick(kAntenna, fields), row);
    if (r.f[kX].present()) {
      out.position = Vec3(number(t, r.f[kX], row), number(t, r.f[kY], row), number(t, r.f[kZ], row));
      if (r.f[kQx].present()) {
        const Eigen::Vector4d q(number(t, r.f[kQx], row), number(t, r.f[kQy], row), number(t, r.f[kQz], row),
                                number(t, r.f[kQw], row));
        if (q.norm() < 1e-9)
          throw InputError(located(t.file, row.line) + "column '" + r.f[kQx].name + "'..'" + r.f[kQw].name +
                           "': quaternion has zero norm");
        out.orientation = Quat(q[3], q[0], q[1], q[2]).normalized();
      }
    }
    return out;
  }
};

// Checks that a carrier can be found for every row (before reading them).
void require_frequency(const Table& t, const Resolved& r, const RealLogOptions& o) {
  if (r.f[kFrequency].present()) return;
  const std::string at = located(t.file, t.header_line);
  if (r.f[kChannel].present()) {
    if (o.channel_plan_hz.empty())
      throw InputError(at + "column '" + r.f[kChannel].name +
                       "': channel indices need a channel plan (--channel-plan fcc|etsi|cn920|LIST of Hz)");
    return;
  }
  if (o.default_frequency_hz <= 0.0)
    throw InputError(at + "column 'frequency': no frequency or channel column (header: " + header_list(t) +
                     "); give the carrier with --frequency-hz or name the column with --columns frequency=NAME");
}

// The layout a header announces, and the column that gave it away.
std::optional<std::pair<LogLayout, std::string>> detect_layout(const Table& t) {
  std::set<std::string> n;
  std::map<std::string, std::string> spelled;
  for (const std::string& h : t.header) {
    n.insert(normalized_name(h));
    spelled[normalized_name(h)] = h;
  }
  if (n.count("epc") && n.count("antennaindex") && n.count("x") && n.count("y") && n.count("z") && n.count("phase"))
    return std::make_pair(LogLayout::kPerStop, spelled["antennaindex"]);
  // Names only one of the two uses first, then the weaker hints.
  for (const char* k : {"phaseangleinradians", "channelinmhz", "peakrssiindbm", "antennaportnumber", "firstseentime",
                        "lastseentime"})
    if (n.count(k)) return std::make_pair(LogLayout::kOctane, spelled[k]);
  for (const char* k : {"impinjrfphaseangle", "impinjphase", "firstseentimestamputc", "lastseentimestamputc", "epc96",
                        "impinjpeakrssi", "antennaid", "channelindex"})
    if (n.count(k)) return std::make_pair(LogLayout::kSllurp, spelled[k]);
  for (const char* k : {"phaseangle", "phaseangleindegrees", "phaseangledeg"})
    if (n.count(k)) return std::make_pair(LogLayout::kOctane, spelled[k]);
  return std::nullopt;
}

bool has_user_columns(const ColumnMap& m) {
  for (int f = 0; f < kFieldCount; ++f)
    if (field_of(m, static_cast<Field>(f)).given()) return true;
  return false;
}

// N.csv files of a directory, by N.
std::vector<std::pair<long long, fs::path>> stop_files(const fs::path& dir) {
  static const std::regex re(R"(^(\d{1,9})\.csv$)", std::regex::icase);
  std::vector<std::pair<long long, fs::path>> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    std::smatch m;
    const std::string name = e.path().filename().string();
    if (e.is_regular_file() && std::regex_match(name, m, re)) out.emplace_back(std::stoll(m[1]), e.path());
  }
  std::sort(out.begin(), out.end());
  return out;
}

RealLog read_per_stop(const fs::path& path, const RealLogOptions& o, RealLog log) {
  std::vector<std::pair<long long, fs::path>> files;
  if (fs::is_directory(path)) {
    files = stop_files(path);
    if (files.empty())
      throw InputError(path.string() + ": no N.csv files in this directory (per-stop layout: 0.csv, 1.csv, ... one "
                                       "per antenna stop)");
  } else {
    // One stop file: its number from the name when it is N.csv.
    long long n = 0;
    std::smatch m;
    const std::string name = path.filename().string();
    if (std::regex_match(name, m, std::regex(R"(^(\d{1,9})\.csv$)"))) n = std::stoll(m[1]);
    files.emplace_back(n, path);
  }
  if (!(o.stop_period_s > 0.0) || !std::isfinite(o.stop_period_s))
    throw InputError("--stop-period-s: must be > 0 (got " + num(o.stop_period_s) + ")");
  Converter conv{o, {}, {}, log.notes};
  struct Pending {
    Table table;
    Resolved resolved;
  };
  std::vector<Pending> stops;
  bool real_times = false;
  for (const auto& [n, file] : files) {
    Pending p{read_table(file, /*allow_no_rows=*/true), {}};
    if (p.table.json) throw InputError(file.string() + ": per-stop files are CSV, this one holds JSON");
    std::vector<std::string> notes;
    p.resolved = resolve(p.table, LogLayout::kPerStop, o.columns, notes);
    require_frequency(p.table, p.resolved, o);
    if (stops.empty()) log.notes.insert(log.notes.end(), notes.begin(), notes.end());
    const Column& tc = p.resolved.f[kTime];
    if (tc.index >= 0)
      for (const Table::Row& row : p.table.rows) {
        const std::optional<double> v = to_number(row.fields[tc.index]);
        if (!v || *v != 0.0) real_times = true;  // a time, or text the time parser will judge
      }
    if (tc.constant && *tc.constant != 0.0) real_times = true;
    stops.push_back(std::move(p));
  }
  if (real_times)
    log.notes.push_back(path.string() + ": per-stop times from the files' time column");
  else
    log.notes.push_back(path.string() + ": per-stop times synthesized: stop N at N x " + num(o.stop_period_s) +
                        " s, its rows spread over the stop in file order (the files' times are all 0)");
  double last_time = -std::numeric_limits<double>::infinity();
  std::string last_where;
  for (size_t s = 0; s < stops.size(); ++s) {
    const Table& t = stops[s].table;
    const double n_rows = static_cast<double>(t.rows.size());
    for (size_t j = 0; j < t.rows.size(); ++j) {
      RealRead r = conv.read(t, stops[s].resolved, t.rows[j], real_times);
      if (!real_times) {
        r.time_s = static_cast<double>(files[s].first) * o.stop_period_s + o.stop_period_s * static_cast<double>(j) / n_rows;
      } else if (r.time_s < last_time) {
        throw InputError(located(t.file, t.rows[j].line) + "column '" + stops[s].resolved.f[kTime].name +
                         "': time goes backwards (" + num(r.time_s) + " s after " + num(last_time) + " s at " +
                         last_where + "); per-stop data must be in stop and row order");
      }
      last_time = r.time_s;
      last_where = t.file + ":" + std::to_string(t.rows[j].line);
      log.reads.push_back(std::move(r));
    }
  }
  if (log.reads.empty()) throw InputError(path.string() + ": no reads in any stop file");
  return log;
}

}  // namespace

LogLayout parse_log_layout(const std::string& name, const std::string& field) {
  if (name == "auto") return LogLayout::kAuto;
  if (name == "octane") return LogLayout::kOctane;
  if (name == "sllurp") return LogLayout::kSllurp;
  if (name == "per-stop") return LogLayout::kPerStop;
  if (name == "columns") return LogLayout::kColumns;
  throw field_error(field, "must be auto, octane, sllurp, per-stop or columns (got '" + name + "')");
}

const char* to_string(LogLayout layout) {
  switch (layout) {
    case LogLayout::kOctane: return "octane";
    case LogLayout::kSllurp: return "sllurp";
    case LogLayout::kPerStop: return "per-stop";
    case LogLayout::kColumns: return "columns";
    default: return "auto";
  }
}

ColumnMap parse_column_map(const std::string& spec) {
  ColumnMap m;
  std::set<std::string> seen;
  static const std::vector<std::string> kUnitKeys = {"phase_unit", "frequency_unit", "time_unit", "rssi_unit"};
  for (const std::string& item_raw : split_csv_line(spec)) {
    const std::string item = trim(item_raw);
    if (item.empty()) continue;
    const size_t eq = item.find('=');
    if (eq == std::string::npos)
      throw InputError("--columns: '" + item + "' is not KEY=VALUE (e.g. phase=PhaseAngle)");
    const std::string key = trim(item.substr(0, eq)), value = trim(item.substr(eq + 1));
    if (value.empty()) throw InputError("--columns: " + key + "= needs a column name");
    if (!seen.insert(key).second) throw InputError("--columns: key '" + key + "' given twice");
    const auto field = std::find(kFieldKeys.begin(), kFieldKeys.end(), key);
    if (field != kFieldKeys.end()) {
      FieldSource& src = field_of(m, static_cast<Field>(field - kFieldKeys.begin()));
      const std::optional<double> constant = to_number(value);
      if (constant && key != "epc") {
        if (!std::isfinite(*constant)) throw InputError("--columns: " + key + "=" + value + " is not finite");
        src.constant = *constant;
      } else {
        src.column = value;
      }
      continue;
    }
    if (std::find(kUnitKeys.begin(), kUnitKeys.end(), key) != kUnitKeys.end()) {
      std::string v;
      for (char c : value) v += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      auto bad = [&](const char* allowed) {
        return InputError("--columns: " + key + "=" + value + ": must be " + allowed);
      };
      if (key == "phase_unit") {
        if (v == "rad" || v == "radians") m.phase_unit = LogUnit::kRad;
        else if (v == "deg" || v == "degrees") m.phase_unit = LogUnit::kDeg;
        else if (v == "impinj" || v == "4096") m.phase_unit = LogUnit::kImpinj12Bit;
        else throw bad("rad, deg or impinj (12-bit, 2pi/4096)");
      } else if (key == "frequency_unit") {
        if (v == "hz") m.frequency_unit = LogUnit::kHz;
        else if (v == "khz") m.frequency_unit = LogUnit::kKhz;
        else if (v == "mhz") m.frequency_unit = LogUnit::kMhz;
        else throw bad("hz, khz or mhz");
      } else if (key == "time_unit") {
        if (v == "s") m.time_unit = LogUnit::kS;
        else if (v == "ms") m.time_unit = LogUnit::kMs;
        else if (v == "us") m.time_unit = LogUnit::kUs;
        else if (v == "ns") m.time_unit = LogUnit::kNs;
        else throw bad("s, ms, us or ns");
      } else {
        if (v == "dbm") m.rssi_unit = LogUnit::kDbm;
        else if (v == "cdbm") m.rssi_unit = LogUnit::kCentiDbm;
        else throw bad("dbm or cdbm (1/100 dBm)");
      }
      continue;
    }
    std::vector<std::string> known(kFieldKeys.begin(), kFieldKeys.end());
    known.insert(known.end(), kUnitKeys.begin(), kUnitKeys.end());
    std::string best, list;
    size_t best_d = 3;
    for (const std::string& k : known) {
      list += (list.empty() ? "" : ", ") + k;
      if (const size_t d = edit_distance(key, k); d < best_d) best_d = d, best = k;
    }
    throw InputError("--columns: unknown key '" + key + "'" + (best.empty() ? "" : " (did you mean '" + best + "'?)") +
                     "; known keys: " + list);
  }
  return m;
}

std::vector<double> parse_channel_plan(const std::string& spec) {
  std::vector<double> plan;
  const std::string s = trim(spec);
  if (s == "fcc") {
    for (int i = 0; i < 50; ++i) plan.push_back(902.75e6 + 0.5e6 * i);
  } else if (s == "etsi" || s == "eu") {
    plan = {865.7e6, 866.3e6, 866.9e6, 867.5e6};
  } else if (s == "cn920") {
    for (int i = 0; i < 16; ++i) plan.push_back(920.625e6 + 0.25e6 * i);
  } else {
    for (const std::string& item : split_csv_line(s)) {
      const std::optional<double> v = to_number(item);
      if (!v || !std::isfinite(*v) || *v < 1e8 || *v > 1e10)
        throw InputError("--channel-plan: '" + trim(item) +
                         "' is not a carrier in Hz (100 MHz .. 10 GHz); give fcc, etsi, cn920 or a list of Hz");
      plan.push_back(*v);
    }
  }
  if (plan.empty()) throw InputError("--channel-plan: empty (give fcc, etsi, cn920 or a list of Hz)");
  return plan;
}

RealLog read_real_log(const fs::path& path, const RealLogOptions& o) {
  RealLog log;
  if (!fs::exists(path)) throw InputError(path.string() + ": no such file or directory");
  if (o.default_frequency_hz != 0.0 && !(o.default_frequency_hz >= 1e8 && o.default_frequency_hz <= 1e10))
    throw InputError("--frequency-hz: " + num(o.default_frequency_hz) + " is not a carrier in Hz (100 MHz .. 10 GHz)");
  LogLayout layout = o.layout;
  if (layout == LogLayout::kAuto && fs::is_directory(path)) {
    layout = LogLayout::kPerStop;
    log.notes.push_back(path.string() + ": a directory: layout per-stop");
  }
  if (layout == LogLayout::kPerStop) {
    log.layout = layout;
    return read_per_stop(path, o, std::move(log));
  }
  if (fs::is_directory(path))
    throw InputError(path.string() + ": is a directory; only the per-stop layout reads directories");

  Table t = read_table(path);
  if (layout == LogLayout::kAuto) {
    const auto found = detect_layout(t);
    if (found && found->first == LogLayout::kPerStop) {
      log.layout = LogLayout::kPerStop;
      log.notes.push_back(t.file + ": layout per-stop (auto-detected from the header: column '" + found->second + "')");
      return read_per_stop(path, o, std::move(log));
    }
    if (found) {
      layout = found->first;
      log.notes.push_back(t.file + ": layout " + to_string(layout) + " (auto-detected from the header: column '" +
                          found->second + "')");
    } else if (has_user_columns(o.columns)) {
      layout = LogLayout::kColumns;
      log.notes.push_back(t.file + ": layout columns (--columns)");
    } else {
      throw InputError(located(t.file, t.header_line) + "cannot tell the layout from the header (" + header_list(t) +
                       "): give --layout octane|sllurp|per-stop or --columns");
    }
  }
  log.layout = layout;
  const Resolved r = resolve(t, layout, o.columns, log.notes);
  require_frequency(t, r, o);
  if (!r.f[kTime].present())
    throw InputError(located(t.file, t.header_line) + "column 'time': no time column (header: " + header_list(t) +
                     "); name it with --columns time=NAME");
  Converter conv{o, {}, {}, log.notes};
  for (const Table::Row& row : t.rows) log.reads.push_back(conv.read(t, r, row, true));
  // Reports of several tags can arrive out of time order: the output is in time order (stable, deterministic).
  std::stable_sort(log.reads.begin(), log.reads.end(),
                   [](const RealRead& a, const RealRead& b) { return a.time_s < b.time_s; });
  return log;
}

std::vector<ReadingRow> to_reading_rows(const RealLog& log, const AntennaPoseOptions& o) {
  if (log.reads.empty()) throw InputError("no reads to convert");
  const RealRead& first = log.reads.front();
  const bool from_columns = first.position.has_value();
  const int sources = from_columns + (o.trajectory != nullptr) + o.fixed_position.has_value();
  if (sources == 0)
    throw InputError(first.file + ": no antenna pose: the log has no x,y,z columns; give --trajectory FILE or "
                                  "--antenna-position X,Y,Z");
  if (sources > 1)
    throw InputError(std::string(first.file) + ": more than one antenna pose source (" +
                     (from_columns ? "the log's x,y,z columns, " : "") + (o.trajectory ? "--trajectory, " : "") +
                     (o.fixed_position ? "--antenna-position" : "") + "): give one");
  std::set<std::string> antennas;
  std::set<double> carriers;
  for (const RealRead& r : log.reads) {
    antennas.insert(r.antenna);
    carriers.insert(r.frequency_hz);
  }
  if (!o.antenna_name.empty() && antennas.size() > 1) {
    std::string list;
    for (const std::string& a : antennas) list += (list.empty() ? "" : ", ") + a;
    throw InputError("--antenna-name: the log has several antennas (" + list +
                     "); one name would merge their phase histories — leave --antenna-name out");
  }
  const std::vector<double> carrier_list(carriers.begin(), carriers.end());
  std::vector<ReadingRow> rows;
  rows.reserve(log.reads.size());
  for (const RealRead& r : log.reads) {
    ReadingRow row;
    row.line = r.line;
    row.time_s = r.time_s + o.time_offset_s;
    const std::string at = located(r.file, r.line);
    if (from_columns) {
      if (!r.position) throw InputError(at + "column 'x','y','z': no antenna position for this read");
      row.antenna_pose.position = *r.position;
      row.antenna_pose.orientation = r.orientation ? *r.orientation : o.orientation;
    } else if (o.trajectory) {
      try {
        row.antenna_pose = o.trajectory->pose_at(row.time_s, o.trajectory_tolerance_s);
      } catch (const InputError& e) {
        throw InputError(at + "read outside the trajectory: " + e.what());
      }
    } else {
      row.antenna_pose.position = *o.fixed_position;
      row.antenna_pose.orientation = o.orientation;
    }
    row.tag = r.epc;
    row.distance_m = 0.0;  // the reader never knows it
    row.phase_rad = r.phase_rad;
    row.rssi = r.rssi_dbm;
    row.antenna = !o.antenna_name.empty() ? o.antenna_name : !r.antenna.empty() ? r.antenna : "antenna";
    row.frequency_hz = r.frequency_hz;
    row.hop_index = static_cast<int>(std::lower_bound(carrier_list.begin(), carrier_list.end(), r.frequency_hz) -
                                     carrier_list.begin());
    if (!std::isfinite(row.time_s) || !row.antenna_pose.position.allFinite() ||
        !row.antenna_pose.orientation.coeffs().allFinite() || !std::isfinite(row.phase_rad) || !std::isfinite(row.rssi))
      throw InputError(at + "a value is not finite after conversion");
    rows.push_back(std::move(row));
  }
  return rows;
}

}  // namespace rfidray::io
