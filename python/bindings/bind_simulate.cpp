// simulate() and load_readings(): a scenario run exactly as `rfidray simulate` runs it (io::load_scenario /
// parse_scenario, build_motion, make_channel, simulate), and a readings CSV read by io::read_readings_csv.
// Both return the CSV's columns as NumPy arrays; rfidray/__init__.py assembles the structured arrays.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include <cmath>
#include <iterator>
#include <map>
#include <memory>
#include <optional>

#include "core/error.h"
#include "core/simulation.h"
#include "raytrace/channel_factory.h"
#include "io/readings_csv.h"
#include "io/scenario_yaml.h"
#include "python/bindings/bindings.h"

namespace rfidray::py {
namespace {

// The numeric columns of the readings CSV (io/readings_csv.h), in file order; name and antenna are strings.
constexpr const char* kNumeric[] = {"time", "posx", "posy", "posz", "q1", "q2", "q3", "q4",
                                    "dist", "phase", "rssi", "frequency_hz"};

struct Columns {
  explicit Columns(size_t n) : n(n) {
    for (const char* c : kNumeric) numeric[c] = pyb::array_t<double>(static_cast<pyb::ssize_t>(n));
    hop = pyb::array_t<int64_t>(static_cast<pyb::ssize_t>(n));
  }
  void set(size_t i, double time_s, const Pose& pose, double dist, double phase, double rssi, double f, int64_t h) {
    const double v[] = {time_s, pose.position.x(), pose.position.y(), pose.position.z(), pose.orientation.x(),
                        pose.orientation.y(), pose.orientation.z(), pose.orientation.w(), dist, phase, rssi, f};
    for (size_t k = 0; k < std::size(kNumeric); ++k) numeric[kNumeric[k]].mutable_at(i) = v[k];
    hop.mutable_at(i) = h;
  }
  pyb::dict dict() const {
    pyb::dict d;
    for (const auto& [name, a] : numeric) d[pyb::str(name)] = a;
    d["channel"] = hop;
    return d;
  }
  size_t n;
  std::map<std::string, pyb::array_t<double>> numeric;
  pyb::array_t<int64_t> hop;
};

pyb::dict run_simulate(std::optional<std::string> path, std::optional<std::string> text, const std::string& source,
                       std::optional<uint64_t> seed, std::optional<std::string> channel,
                       std::optional<std::string> model, std::optional<double> duration_s, int threads) {
  Scenario scenario = path ? io::load_scenario(*path) : io::parse_scenario(text.value_or(""), source);
  // The overrides of `rfidray simulate --seed --channel --model --duration`.
  if (duration_s) {
    if (!(*duration_s >= 0.0) || !std::isfinite(*duration_s)) throw field_error("duration_s", "must be a finite number >= 0");
    scenario.duration_s = *duration_s;
  }
  if (seed) scenario.seed = *seed;
  if (channel) scenario.channel = parse_channel_level(*channel, "channel");
  if (model) {
    if (*model != "paper" && *model != "physical") throw field_error("model", "must be paper or physical (got '" + *model + "')");
    for (AntennaSpec& a : scenario.antennas)
      a.reader.model = *model == "physical" ? ReaderModelKind::kPhysical : ReaderModelKind::kPaper;
  }
  if (threads < 0 || threads > 1024) throw field_error("threads", "must be in 0…1024 (0: OpenMP default)");
  std::vector<std::string> report;
  SimulationResult result;
  std::string channel_name;
  SceneMotion motion;
  {
    pyb::gil_scoped_release release;
    motion = build_motion(scenario);
    const std::unique_ptr<Channel> ch = make_channel(scenario.channel, scenario, motion, &report);
    channel_name = ch->name();
    SimulationOptions sim;
    sim.threads = threads;
    result = simulate(scenario, motion, *ch, sim);
  }
  pyb::list antennas;
  for (size_t a = 0; a < scenario.antennas.size(); ++a) {
    const AntennaResult& r = result.antennas[a];
    Columns c(r.reads.size());
    pyb::array_t<uint32_t> tag(static_cast<pyb::ssize_t>(r.reads.size()));
    for (size_t i = 0; i < r.reads.size(); ++i) {
      const ReadRecord& rec = r.reads[i];
      c.set(i, rec.time_s, rec.antenna_pose, rec.distance_m, rec.reading.phase_rad, rec.reading.rssi_dbm,
            rec.frequency_hz, rec.hop_index);
      tag.mutable_at(i) = rec.tag;
    }
    pyb::dict d = c.dict();
    d["tag_index"] = tag;
    antennas.append(pyb::make_tuple(scenario.antennas[a].reader.name, d, r.ticks, r.attempts));
  }
  pyb::list tags;
  for (size_t i = 0; i < scenario.tags.size(); ++i) {
    const Vec3 p = motion.tags[i]->pose_at(0.0).position;  // tags.csv: positions at t = 0
    tags.append(pyb::make_tuple(scenario.tags[i].tag.name, p.x(), p.y(), p.z()));
  }
  pyb::dict out;
  out["antennas"] = antennas;
  out["tags"] = tags;
  out["channel"] = channel_name;
  out["duration_s"] = result.duration_s;
  out["seed"] = scenario.seed;
  out["report"] = report;
  return out;
}

pyb::dict load_readings(const std::string& path) {
  const std::vector<io::ReadingRow> rows = io::read_readings_csv(path);
  Columns c(rows.size());
  pyb::list name, antenna;
  for (size_t i = 0; i < rows.size(); ++i) {
    const io::ReadingRow& r = rows[i];
    c.set(i, r.time_s, r.antenna_pose, r.distance_m, r.phase_rad, r.rssi, r.frequency_hz, r.hop_index);
    name.append(r.tag);
    antenna.append(r.antenna);
  }
  pyb::dict d = c.dict();
  d["name"] = name;
  d["antenna"] = antenna;
  return d;
}

}  // namespace

void bind_simulate(pyb::module_& m) {
  m.def("_simulate", &run_simulate, pyb::arg("path"), pyb::arg("text"), pyb::arg("source"), pyb::arg("seed"),
        pyb::arg("channel"), pyb::arg("model"), pyb::arg("duration_s"), pyb::arg("threads"));
  m.def("_load_readings", &load_readings, pyb::arg("path"));
}

}  // namespace rfidray::py
