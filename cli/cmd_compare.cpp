// `rfidray compare SCENARIO`: the same scenario and seed through the ideal channel and a ray-traced one.
// Per antenna and tag: phase error (wrapped to (−π, π], rad) and RSSI difference (dB) over the ticks where
// both read the tag, and the change in read count; a PNG of phase and RSSI along the trajectory for chosen tags.
//
// Both runs draw the same noise (per-tick random streams, core/random.h), so the differences are the
// channel's. The paper reader model ignores the channel (eq. 4–5 use the distance only), so antennas using it
// are switched to the physical model for both runs, and compare says so.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <sstream>

#include "io/atomic_file.h"
#include "raytrace/channel_factory.h"
#include "io/plot.h"
#include "io/scenario_yaml.h"
#include "core/error.h"
#include "core/simulation.h"
#include "core/units.h"
#include "core/thread_count.h"

namespace rfidray::cli {
namespace {

struct CompareOptions {
  std::string scenario;
  std::optional<uint64_t> seed;
  std::string tags;
  std::string output_dir = "out/compare";
  std::string channel = "single-bounce";
  std::string antenna;
  int threads = 0;
};

struct Stats {
  size_t n = 0;
  double sum = 0.0, sum2 = 0.0, min = INFINITY, max = -INFINITY, max_abs = 0.0;
  void add(double v) {
    ++n;
    sum += v;
    sum2 += v * v;
    min = std::min(min, v);
    max = std::max(max, v);
    max_abs = std::max(max_abs, std::abs(v));
  }
  double mean() const { return n ? sum / n : 0.0; }
  double rms() const { return n ? std::sqrt(sum2 / n) : 0.0; }
};

struct TagCompare {
  size_t reads_ideal = 0, reads_traced = 0;
  Stats phase_rad, rssi_db;
};

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

int run_compare(const CompareOptions& o) {
  Scenario scenario = io::load_scenario(o.scenario);
  if (o.seed) scenario.seed = *o.seed;
  const ChannelLevel level = parse_channel_level(o.channel, "--channel");
  if (level == ChannelLevel::kIdeal)
    throw InputError("option --channel: compare needs a ray-traced level (los, los+blocked, single-bounce, double-bounce, "
                     "full-selective, full, auto)");
  for (AntennaSpec& a : scenario.antennas)
    if (a.reader.model == ReaderModelKind::kPaper) {
      std::cerr << "rfidray: note: antenna '" << a.reader.name
                << "' uses the paper model, which ignores the channel; compare runs it with the physical model\n";
      a.reader.model = ReaderModelKind::kPhysical;
    }
  const SceneMotion motion = build_motion(scenario);
  const IdealChannel ideal;
  const std::unique_ptr<Channel> traced = make_channel(level, scenario, motion);
  SimulationOptions sim;
  const ThreadCount threads = startable_threads(o.threads, "--threads");
  if (!threads.note.empty()) std::cerr << "rfidray: warning: " << threads.note << "\n";
  sim.threads = threads.threads;
  const SimulationResult ri = simulate(scenario, motion, ideal, sim);
  const SimulationResult rt = simulate(scenario, motion, *traced, sim);

  // Chosen tags for the plot (default: the first two).
  std::vector<size_t> plot_tags;
  for (const std::string& name : split_list(o.tags)) {
    size_t i = 0;
    while (i < scenario.tags.size() && scenario.tags[i].tag.name != name) ++i;
    if (i == scenario.tags.size()) throw InputError("option --tags: no tag named '" + name + "' in " + o.scenario);
    plot_tags.push_back(i);
  }
  if (o.tags.empty())
    for (size_t i = 0; i < std::min<size_t>(2, scenario.tags.size()); ++i) plot_tags.push_back(i);
  size_t plot_antenna = 0;
  if (!o.antenna.empty()) {
    while (plot_antenna < scenario.antennas.size() && scenario.antennas[plot_antenna].reader.name != o.antenna) ++plot_antenna;
    if (plot_antenna == scenario.antennas.size()) throw InputError("option --antenna: no antenna named '" + o.antenna + "'");
  }
  if (scenario.antennas.empty()) throw InputError(o.scenario + ": no antennas");

  const std::filesystem::path dir(o.output_dir);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(o.output_dir + ": cannot create output directory (" + ec.message() + ")");
  io::check_output_path(dir / "compare.csv", "compare.csv");
  std::ostringstream csv;  // written atomically at the end (io/atomic_file.h)
  csv << "antenna,tag,reads_ideal,reads_raytraced,both,phase_err_mean_rad,phase_err_rms_rad,phase_err_max_abs_rad,"
         "rssi_diff_mean_db,rssi_diff_rms_db,rssi_diff_min_db,rssi_diff_max_db\n";
  csv.precision(6);

  std::printf("rfidray compare %s: ideal vs %s, seed %llu, %.3f s\n", o.scenario.c_str(), o.channel.c_str(),
              static_cast<unsigned long long>(scenario.seed), ri.duration_s);
  std::vector<io::Panel> panels;
  for (size_t a = 0; a < scenario.antennas.size(); ++a) {
    const auto& ai = ri.antennas[a].reads;
    const auto& at = rt.antennas[a].reads;
    std::vector<TagCompare> per_tag(scenario.tags.size());
    // Reads are ordered by (tick, tag): merge the two lists.
    size_t i = 0, j = 0;
    while (i < ai.size() || j < at.size()) {
      const bool take_i = j == at.size() || (i < ai.size() && std::tie(ai[i].tick, ai[i].tag) <= std::tie(at[j].tick, at[j].tag));
      const bool take_j = i == ai.size() || (j < at.size() && std::tie(at[j].tick, at[j].tag) <= std::tie(ai[i].tick, ai[i].tag));
      if (take_i && take_j) {
        TagCompare& c = per_tag[ai[i].tag];
        c.phase_rad.add(wrap_to_pi(at[j].reading.phase_rad - ai[i].reading.phase_rad));
        c.rssi_db.add(at[j].reading.rssi_dbm - ai[i].reading.rssi_dbm);
      }
      if (take_i) ++per_tag[ai[i++].tag].reads_ideal;
      if (take_j) ++per_tag[at[j++].tag].reads_traced;
    }
    const std::string& an = scenario.antennas[a].reader.name;
    std::printf("\nantenna %s: reads %zu ideal, %zu %s (%+.1f %%), of %llu attempts\n", an.c_str(), ai.size(), at.size(),
                o.channel.c_str(), ai.empty() ? 0.0 : 100.0 * (double(at.size()) - double(ai.size())) / double(ai.size()),
                static_cast<unsigned long long>(ri.antennas[a].attempts));
    std::printf("  %-10s %7s %7s %6s | %9s %9s %9s | %8s %8s %8s %8s\n", "tag", "ideal", "traced", "both",
                "phi_mean", "phi_rms", "phi_max", "dB_mean", "dB_rms", "dB_min", "dB_max");
    for (size_t t = 0; t < per_tag.size(); ++t) {
      const TagCompare& c = per_tag[t];
      const std::string& tn = scenario.tags[t].tag.name;
      std::printf("  %-10s %7zu %7zu %6zu | %9.4f %9.4f %9.4f | %8.2f %8.2f %8.2f %8.2f\n", tn.c_str(), c.reads_ideal,
                  c.reads_traced, c.phase_rad.n, c.phase_rad.mean(), c.phase_rad.rms(), c.phase_rad.max_abs,
                  c.rssi_db.mean(), c.rssi_db.rms(), c.rssi_db.n ? c.rssi_db.min : 0.0, c.rssi_db.n ? c.rssi_db.max : 0.0);
      csv << an << ',' << tn << ',' << c.reads_ideal << ',' << c.reads_traced << ',' << c.phase_rad.n << ','
          << c.phase_rad.mean() << ',' << c.phase_rad.rms() << ',' << c.phase_rad.max_abs << ',' << c.rssi_db.mean()
          << ',' << c.rssi_db.rms() << ',' << (c.rssi_db.n ? c.rssi_db.min : 0.0) << ','
          << (c.rssi_db.n ? c.rssi_db.max : 0.0) << '\n';
    }
    if (a != plot_antenna) continue;
    for (size_t t : plot_tags) {
      const std::string& tn = scenario.tags[t].tag.name;
      if (per_tag[t].reads_ideal == 0 && per_tag[t].reads_traced == 0) {
        std::printf("  tag '%s' has no reads at antenna %s (ideal or %s): nothing to plot for it\n", tn.c_str(),
                    an.c_str(), o.channel.c_str());
        continue;
      }
      io::Panel phase{"antenna " + an + ", " + tn + ": phase", "time along the trajectory (s)", "phase (rad)", {}};
      io::Panel rssi{"antenna " + an + ", " + tn + ": RSSI", "time along the trajectory (s)", "RSSI (dBm)", {}};
      for (int which = 0; which < 2; ++which) {
        const auto& reads = which == 0 ? ai : at;
        io::Series sp{which == 0 ? "ideal" : o.channel, {}, {}, "points"};
        io::Series sr{which == 0 ? "ideal" : o.channel, {}, {}, "lines"};
        for (const ReadRecord& r : reads)
          if (r.tag == t) {
            sp.x.push_back(r.time_s);
            sp.y.push_back(r.reading.phase_rad);
            sr.x.push_back(r.time_s);
            sr.y.push_back(r.reading.rssi_dbm);
          }
        if (sp.x.empty()) continue;  // this run never read the tag: only the other is drawn
        phase.series.push_back(std::move(sp));
        rssi.series.push_back(std::move(sr));
      }
      panels.push_back(std::move(phase));
      panels.push_back(std::move(rssi));
    }
  }
  io::write_file_atomic(dir / "compare.csv", [&](std::ostream& out) { out << csv.str(); }, "compare.csv");
  std::printf("\n-> %s\n", (dir / "compare.csv").string().c_str());
  if (panels.empty()) {
    std::printf("-> no chart: the plotted tags have no reads\n");
  } else {
    io::write_png(dir / "compare.png", panels, 1100, 300);
    std::printf("-> %s\n", (dir / "compare.png").string().c_str());
  }
  return 0;
}

}  // namespace

std::function<int()> setup_compare(CLI::App& app) {
  auto o = std::make_shared<CompareOptions>();
  CLI::App* cmd = app.add_subcommand("compare", "Same scenario and seed, ideal vs ray-traced channel: phase/RSSI differences per tag");
  cmd->add_option("scenario", o->scenario, "Scenario YAML file")->required();
  cmd->add_option("--seed", o->seed, "Random seed (overrides the scenario's), >= 0")->check(CLI::NonNegativeNumber);
  cmd->add_option("--tags", o->tags, "Tags to plot, comma-separated names (default: the first two)");
  cmd->add_option("--antenna", o->antenna, "Antenna to plot (default: the first)");
  cmd->add_option("--channel", o->channel, "Ray-traced level: los | los+blocked | single-bounce | double-bounce | full-selective | full | auto");
  cmd->add_option("--threads", o->threads, "OpenMP threads (default: all), 1…1024")->check(CLI::Range(1, 1024));
  cmd->add_option("-o,--output", o->output_dir, "Output directory (compare.csv, compare.png)");
  return [o] { return run_compare(*o); };
}

}  // namespace rfidray::cli
