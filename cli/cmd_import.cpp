// `rfidray import`: real reader logs (Impinj Octane / ItemTest, sllurp, per-stop directories, any CSV through a
// column map) → one readings CSV that `localize` reads. Parsing lives in io/real_log and io/trajectory_csv.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <set>

#include "core/error.h"
#include "core/units.h"
#include "io/checked_yaml.h"
#include "io/csv_fields.h"
#include "io/readings_csv.h"
#include "io/real_log.h"
#include "io/trajectory_csv.h"
#include "core/number_text.h"

namespace rfidray::cli {

namespace {

namespace fs = std::filesystem;

struct ImportState {
  std::string input;
  std::string output;
  std::string layout = "auto";
  std::string columns;
  std::string channel_plan;
  double frequency_hz = 0.0;
  std::string trajectory;
  double trajectory_tolerance_s = 0.0;
  std::string antenna_position;
  std::string antenna_rpy = "0,0,0";
  double stop_period_s = 1.0;
  double time_offset_s = 0.0;
  std::string antenna_name;
  std::string tags_out;
  bool negate_phase = false;
  bool quiet = false;
};

Vec3 parse_triple(const std::string& text, const std::string& option) {
  const std::vector<std::string> f = io::split_csv_line(text);
  if (f.size() != 3) throw field_error(option, "needs three comma-separated numbers (got '" + text + "')");
  Vec3 v;
  for (int i = 0; i < 3; ++i) {
    const std::optional<double> x = io::to_number(f[i]);
    if (!x || !std::isfinite(*x)) throw field_error(option, "'" + io::trim(f[i]) + "' is not a finite number");
    v[i] = *x;
  }
  return v;
}

// Writes through a temporary file in the target's directory, renamed over the target when complete: a failure
// leaves no half-written file.
void write_atomically(const fs::path& target, const std::function<void(std::ostream&)>& write) {
  if (fs::is_directory(target)) throw InputError(target.string() + ": is a directory, expected a file name");
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  if (!fs::is_directory(dir)) throw InputError(target.string() + ": directory '" + dir.string() + "' does not exist");
  const fs::path tmp = dir / ("." + target.filename().string() + ".tmp" + std::to_string(::getpid()));
  try {
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      if (!out) throw InputError(target.string() + ": cannot write in '" + dir.string() + "'");
      write(out);
      out.flush();
      if (!out) throw InputError(target.string() + ": write failed (disk full?)");
    }
    fs::rename(tmp, target);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

std::string mhz(double hz) { return num(hz / 1e6); }

// Times to the millisecond (epoch times have ten digits before the point).
std::string seconds(double t) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3f", t);
  return buf;
}

int run_import(const ImportState& s) {
  io::RealLogOptions o;
  o.layout = io::parse_log_layout(s.layout);
  if (!s.columns.empty()) o.columns = io::parse_column_map(s.columns);
  if (o.layout == io::LogLayout::kColumns && s.columns.empty())
    throw field_error("--layout columns", "needs --columns KEY=COLUMN,... (epc, phase, rssi, time, frequency, ...)");
  if (!s.channel_plan.empty()) o.channel_plan_hz = io::parse_channel_plan(s.channel_plan);
  o.default_frequency_hz = s.frequency_hz;
  o.stop_period_s = s.stop_period_s;
  o.negate_phase = s.negate_phase;
  if (!std::isfinite(s.time_offset_s)) throw field_error("--time-offset-s", "must be finite");
  if (!(s.trajectory_tolerance_s >= 0.0) || !std::isfinite(s.trajectory_tolerance_s))
    throw field_error("--trajectory-tolerance-s", "must be >= 0");

  io::AntennaPoseOptions pose;
  pose.orientation = io::quat_from_rpy(parse_triple(s.antenna_rpy, "--antenna-rpy") * (kPi / 180.0));
  if (!s.antenna_position.empty()) pose.fixed_position = parse_triple(s.antenna_position, "--antenna-position");
  std::optional<io::RecordedTrajectory> trajectory;
  if (!s.trajectory.empty()) {
    trajectory = io::read_trajectory_csv(s.trajectory);
    pose.trajectory = &*trajectory;
    pose.trajectory_tolerance_s = s.trajectory_tolerance_s;
  }
  pose.time_offset_s = s.time_offset_s;
  pose.antenna_name = s.antenna_name;
  if (!s.antenna_name.empty() && s.antenna_name.find_first_of(",\"\n") != std::string::npos)
    throw field_error("--antenna-name", "must not hold a comma or quote");

  const io::RealLog log = io::read_real_log(s.input, o);
  if (!s.quiet)
    for (const std::string& n : log.notes) std::cerr << "rfidray: note: " << n << "\n";
  const std::vector<io::ReadingRow> rows = io::to_reading_rows(log, pose);

  write_atomically(s.output, [&](std::ostream& out) { io::write_readings_csv(out, rows); });

  std::set<std::string> antennas;
  std::set<double> carriers;
  std::map<std::string, std::vector<const io::ReadingRow*>> by_tag;
  double t0 = rows.front().time_s, t1 = rows.front().time_s;
  for (const io::ReadingRow& r : rows) {
    antennas.insert(r.antenna);
    carriers.insert(r.frequency_hz);
    by_tag[r.tag].push_back(&r);
    t0 = std::min(t0, r.time_s);
    t1 = std::max(t1, r.time_s);
  }
  if (!s.tags_out.empty())
    write_atomically(s.tags_out, [&](std::ostream& out) {
      out << "name,reads,first_time,last_time,max_rssi\n";
      for (const auto& [tag, reads] : by_tag) {
        double first = reads.front()->time_s, last = first, max_rssi = reads.front()->rssi;
        for (const io::ReadingRow* r : reads) {
          first = std::min(first, r->time_s);
          last = std::max(last, r->time_s);
          max_rssi = std::max(max_rssi, r->rssi);
        }
        out << tag << ',' << reads.size() << ',' << num(first) << ',' << num(last) << ',' << num(max_rssi)
            << '\n';
      }
    });

  std::string antenna_list;
  for (const std::string& a : antennas) antenna_list += (antenna_list.empty() ? "" : ", ") + a;
  std::cout << "imported " << rows.size() << " reads, " << by_tag.size() << " tags, " << carriers.size()
            << (carriers.size() == 1 ? " carrier (" : " carriers (") << mhz(*carriers.begin())
            << (carriers.size() > 1 ? " .. " + mhz(*carriers.rbegin()) : std::string()) << " MHz), " << antennas.size()
            << (antennas.size() == 1 ? " antenna (" : " antennas (") << antenna_list << "), time " << seconds(t0)
            << " .. " << seconds(t1) << " s (span " << seconds(t1 - t0) << " s), layout " << io::to_string(log.layout)
            << " -> " << s.output << "\n";
  return 0;
}

}  // namespace

std::function<int()> setup_import(CLI::App& app) {
  auto s = std::make_shared<ImportState>();
  CLI::App* cmd = app.add_subcommand(
      "import",
      "Convert a real reader log into a readings CSV (time,posx,...,phase,rssi,antenna,frequency_hz,channel) for "
      "`rfidray localize`. Layouts: octane (Impinj Octane SDK / ItemTest CSV), sllurp (LLRP tag reports, JSON lines "
      "or CSV), per-stop (a directory of N.csv files, one per antenna stop), columns (any CSV via --columns); "
      "detected from the header unless --layout is given. Phase is converted to radians in [0, 2pi); dist is "
      "written as 0 (a reader never knows it). Errors name FILE:LINE and the column and exit 2; the output is "
      "written to a temporary file and renamed when complete.");
  cmd->add_option("log", s->input, "the reader log (file), or the directory of N.csv files (per-stop)")->required();
  cmd->add_option("-o,--output", s->output, "readings CSV to write")->required();
  cmd->add_option("--layout", s->layout, "auto | octane | sllurp | per-stop | columns")->capture_default_str();
  cmd->add_option("--columns", s->columns,
                  "column map KEY=COLUMN,...: epc, phase, frequency, channel, rssi, time, antenna, x, y, z, qx, qy, "
                  "qz, qw; units phase_unit=rad|deg|impinj, frequency_unit=hz|khz|mhz, time_unit=s|ms|us|ns, "
                  "rssi_unit=dbm|cdbm. A number instead of a column name is a constant (y=0). With a layout it "
                  "overrides that layout's columns");
  cmd->add_option("--channel-plan", s->channel_plan,
                  "LLRP ChannelIndex (1-based) -> carrier: fcc (902.75-927.25 MHz, 50 x 500 kHz), etsi|eu (865.7, "
                  "866.3, 866.9, 867.5 MHz), cn920 (920.625-924.375 MHz, 16 x 250 kHz) or a comma list of Hz");
  cmd->add_option("--frequency-hz", s->frequency_hz, "carrier (Hz) when the log has neither frequency nor channel");
  cmd->add_option("--trajectory", s->trajectory,
                  "antenna trajectory CSV time,x,y,z,qx,qy,qz,qw (s, m, quaternion): positions interpolated "
                  "linearly to each read's time, orientations by slerp");
  cmd->add_option("--trajectory-tolerance-s", s->trajectory_tolerance_s,
                  "reads up to this long before/after the trajectory take its first/last pose (default: none)");
  cmd->add_option("--antenna-position", s->antenna_position, "fixed antenna position X,Y,Z (m)");
  cmd->add_option("--antenna-rpy", s->antenna_rpy,
                  "antenna orientation roll,pitch,yaw (deg; fixed axes X, Y, Z) for a fixed position and for logs "
                  "with x,y,z but no quaternion columns; boresight = local +X (facing +y: 0,0,90)")
      ->capture_default_str();
  cmd->add_option("--stop-period-s", s->stop_period_s, "per-stop: time between stops (s) when the files' times are 0")
      ->capture_default_str();
  cmd->add_option("--time-offset-s", s->time_offset_s,
                  "added to every log time (s), e.g. the reader clock's offset to the trajectory's");
  cmd->add_option("--antenna-name", s->antenna_name,
                  "antenna column of the output (default port<N> from the log's antenna port, or 'antenna')");
  cmd->add_option("--tags-out", s->tags_out, "also write the EPCs seen: name,reads,first_time,last_time,max_rssi");
  cmd->add_flag("--negate-phase", s->negate_phase, "phase -> -phase (readers whose phase falls with distance)");
  cmd->add_flag("-q,--quiet", s->quiet, "no notes on stderr");
  return [s] { return run_import(*s); };
}

}  // namespace rfidray::cli
