// `rfidray coverage`: read coverage of a deployment over a plane, a box or the scenario's tags (planning/coverage_map.h):
// the CSV and, for a plane or tags, floor-plan heatmaps per antenna. Cells are shared over MPI ranks.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli/commands.h"
#include "cli/planning.h"
#include "core/error.h"
#include "io/atomic_file.h"
#include "io/coverage_csv.h"
#include "io/map_plot.h"
#include "parallel/ranks.h"

namespace rfidray::cli {
namespace {

struct CoverageOptions {
  PlanningOptions plan;
  std::vector<std::string> antennas;  // names; empty: all
  bool no_validity = false;           // skip the per-cell validity verdict (outside_validity, validity_error empty)
};

int run_coverage(const CoverageOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  const parallel::Ranks& ranks = parallel::Ranks::world();
  Planning p = prepare_planning(o.plan);
  std::vector<size_t> antennas;
  if (o.antennas.empty()) {
    for (size_t a = 0; a < p.scenario.antennas.size(); ++a) antennas.push_back(a);
  } else {
    for (const std::string& name : o.antennas) {
      size_t a = 0;
      while (a < p.scenario.antennas.size() && p.scenario.antennas[a].reader.name != name) ++a;
      if (a == p.scenario.antennas.size()) {
        std::string known;
        for (const AntennaSpec& s : p.scenario.antennas) known += (known.empty() ? "" : ", ") + s.reader.name;
        throw InputError("option --antenna: no antenna '" + clip(name) + "' in " + p.source + " (antennas: " + known + ")");
      }
      antennas.push_back(a);
    }
  }
  const std::filesystem::path dir(o.plan.output_dir);
  if (ranks.root()) {
    make_output_dir(o.plan.output_dir);
    io::check_output_path(dir / "coverage.csv", "coverage CSV");
  }
  const auto t_setup = std::chrono::steady_clock::now();
  const std::vector<planning::CoverageValues> values = sharded_coverage(p, antennas, o.plan, "coverage", false, !o.no_validity);
  const auto t_computed = std::chrono::steady_clock::now();
  if (!ranks.root()) return 0;

  std::vector<std::string> names;
  for (size_t a : antennas) names.push_back(p.scenario.antennas[a].reader.name);
  io::write_file_atomic(dir / "coverage.csv",
                        [&](std::ostream& out) { io::write_coverage_csv(out, names, p.cells, values); }, "coverage CSV");
  std::vector<std::string> pngs;
  const bool drawable = p.grid ? p.nx > 0 : !o.plan.box.empty() ? false : true;
  if (!o.plan.no_png && drawable) {
    for (size_t k = 0; k < antennas.size(); ++k) {
      const std::string& n = names[k];
      const bool moving = !p.motion.antennas[antennas[k]]->is_static();
      struct Layer {
        const char* key;
        const std::vector<double>* v;
        std::string label;
        bool reversed;
        std::optional<std::pair<double, double>> range;
      };
      std::vector<Layer> layers = {
          {"read_probability", &values[k].read_probability,
           moving ? "read probability per pass" : "read probability per attempt", false, std::make_pair(0.0, 1.0)},
          {"rssi_dbm", &values[k].rssi_dbm, "RSSI (dBm, noise-free)", false, std::nullopt},
          {"phase_error_rad", &values[k].phase_error_rad, "multipath phase error (rad, vs free space)", true,
           std::nullopt}};
      if (moving)
        layers.push_back({"localization_bound_m", &values[k].localization_bound_m,
                          "localization bound (m, Cramér–Rao RMS)", true, std::nullopt});
      // Where the level cannot be trusted: its estimated error, when cells were judged (planning/coverage_map.h).
      if (std::any_of(values[k].validity_error.begin(), values[k].validity_error.end(),
                      [](double e) { return std::isfinite(e); }))
        layers.push_back({"validity_error", &values[k].validity_error,
                          "estimated error of level " + p.channel->name() + " (fraction of the free-space field)", true,
                          std::make_pair(0.0, 0.5)});
      char buf[32];
      std::snprintf(buf, sizeof buf, "%.2f m", p.plane_z);
      const std::string height = buf;
      for (const Layer& l : layers) {
        io::FloorMap m = floor_map(p, {antennas[k]}, *l.v,
                                   "antenna " + n + ": " + l.label + " (channel " + p.channel->name() + ", " +
                                       (p.grid ? "z = " + height
                                               : o.plan.view == "side" ? std::string("tags, side view")
                                                                       : "tags, seen from above; plan cut at z = " + height) + ")",
                                   l.label, o.plan.view);
        m.range = l.range;
        m.reversed_palette = l.reversed;
        m.log_scale = std::string(l.key) == "localization_bound_m";
        const std::filesystem::path png = dir / ("coverage_" + n + "_" + l.key + ".png");
        io::write_map_png(png, m);
        pngs.push_back(png.string());
      }
    }
  }
  const auto t_end = std::chrono::steady_clock::now();
  if (o.plan.quiet) return 0;
  auto secs = [](auto a, auto b) { return std::chrono::duration<double>(b - a).count(); };
  std::printf("rfidray coverage %s: %zu cells, channel %s%s, %d rank%s\n", p.source.c_str(), p.cells.size(),
              to_string(p.scenario.channel),
              p.scenario.channel == ChannelLevel::kAuto ? (" -> " + p.channel->name()).c_str() : "", ranks.size(),
              ranks.size() == 1 ? "" : "s");
  for (const std::string& line : p.channel_report) std::printf("  %s\n", line.c_str());
  for (size_t k = 0; k < antennas.size(); ++k) {
    size_t read50 = 0, read95 = 0, with_bound = 0, within_1cm = 0, within_5cm = 0;
    for (size_t i = 0; i < p.cells.size(); ++i) {
      const double pr = values[k].read_probability[i], b = values[k].localization_bound_m[i];
      read50 += pr >= 0.5;
      read95 += pr >= 0.95;
      if (std::isfinite(b)) ++with_bound, within_1cm += b <= 0.01, within_5cm += b <= 0.05;
    }
    std::printf("  antenna %s: %zu cells read with p >= 0.5, %zu with p >= 0.95 (of %zu)", names[k].c_str(), read50,
                read95, p.cells.size());
    if (with_bound)
      std::printf("; localization bound (Cramer-Rao RMS) <= 1 cm at %zu cells, <= 5 cm at %zu, defined at %zu", within_1cm,
                  within_5cm, with_bound);
    std::printf("\n");
    // Where the level itself cannot be trusted (planning/coverage_map.h: judged from the antenna's first pose).
    size_t judged = 0, outside = 0;
    for (size_t i = 0; i < p.cells.size(); ++i)
      if (std::isfinite(values[k].outside_validity[i])) ++judged, outside += values[k].outside_validity[i] > 0.5;
    if (judged)
      std::printf("    %zu of %zu cells are where level %s is outside its validity or what was checked (near metal "
                  "edges and edge ends, narrow obstacles, penetrable slabs, parallel plates, plates seen edge-on; docs/fullwave.md): "
                  "coverage.csv's outside_validity, validity_error\n",
                  outside, judged, p.channel->name().c_str());
  }
  std::printf("  -> %s\n", (dir / "coverage.csv").string().c_str());
  for (const std::string& png : pngs) std::printf("  -> %s\n", png.c_str());
  std::printf("  wall time %.3f s: setup %.3f s, coverage %.3f s, output %.3f s\n", secs(t0, t_end), secs(t0, t_setup),
              secs(t_setup, t_computed), secs(t_computed, t_end));
  return 0;
}

}  // namespace

std::function<int()> setup_coverage(CLI::App& app) {
  auto o = std::make_shared<CoverageOptions>();
  CLI::App* cmd = app.add_subcommand("coverage", "Read-coverage maps of a deployment: read probability, RSSI, multipath "
                                                 "phase error, localization bound (CSV + PNG)");
  cmd->footer(
      "Cells: --plane z=H (a grid of --step over --extent or the scene), --box, or --tags (the scenario's tags,\n"
      "including tag_sets). Per antenna and cell (planning/coverage_map.h): read probability (fixed antenna: per\n"
      "attempt, averaged over its carriers; moving antenna: at least once per pass), noise-free RSSI, the\n"
      "multipath phase error against free space, and for a moving antenna the Cramer-Rao bound of the tag's\n"
      "position from the pass's phase history. Same physics as simulate/link; deterministic (no draws).\n"
      "Output in DIR: coverage.csv (antenna,x,y,z,read_probability,rssi_dbm,phase_error_rad,localization_bound_m,\n"
      "outside_validity,validity_error;\n"
      "empty where a value does not exist) and coverage_<antenna>_<value>.png (plane or tags).\n"
      "Scale out: mpirun -n N rfidray coverage ... (cells shared over ranks; the files are identical to 1 rank).");
  add_planning_options(*cmd, o->plan);
  cmd->add_option("--antenna", o->antennas, "only these antennas (repeatable; default: all)");
  cmd->add_flag("--no-validity", o->no_validity,
                "skip each cell's validity verdict (its columns empty): it costs up to half a trace per cell at levels "
                "full-selective and full (docs/commands.md)");
  cmd->add_option("-o,--output", o->plan.output_dir, "output directory (default out/coverage)");
  return [o] { return run_coverage(*o); };
}

}  // namespace rfidray::cli
