// `rfidray bench [--quick] [-o DIR]`: runs the benchmark programs built beside rfidray (build/bench/) and
// collects their CSV and PNG output in DIR (default bench/results):
//   bench_rays      Google Benchmark: our rays vs a raw Embree loop → rays.json, rays.csv, rays_ratio.csv/png
//   bench_sweep     links/s per level, threads, scene size, tags → links_*.csv/png
//   bench_accuracy  accuracy vs speed against the exhaustive reference → accuracy_*.csv, accuracy_pareto.png
//   localize_paper  the paper's localization table, ideal channel and single-bounce → localize_paper_*/
//   localize_sweeps stability of the localization methods → localize_sweep_*.csv/png
// and writes DIR/summary.md (machine, date, the headline figures). Timing lives here, never in tests.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/atomic_file.h"
#include "io/plot.h"
#include "core/error.h"

namespace rfidray::cli {
namespace {

namespace fs = std::filesystem;

struct BenchOptions {
  bool quick = false;
  std::string output_dir;  // "": bench/results for a full run; a quick run goes to out/bench-quick
  std::string only;  // comma-separated subset of the programs
  bool dry_run = false;  // print the output directory and the commands, run nothing, create nothing
};

// The output directory of a run: -o when given, else bench/results for a full run (the committed results) and
// out/bench-quick for a quick one, so a quick run never lands on the committed full-run results (which a user
// would then see as changes to the repository). Relative to the current directory.
fs::path output_directory(const BenchOptions& o) {
  return fs::absolute(!o.output_dir.empty() ? fs::path(o.output_dir)
                      : o.quick             ? fs::path("out") / "bench-quick"
                                            : fs::path("bench") / "results");
}

std::string quoted(const std::string& s) { return "'" + s + "'"; }

fs::path bench_dir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return (ec ? fs::current_path() : exe.parent_path()) / "bench";
}

void run_program(const fs::path& program, const std::string& args, const fs::path& log, bool dry_run) {
  if (dry_run) {  // the plan only: nothing is checked, run or written
    std::printf("rfidray bench (dry run): %s %s > %s\n", program.string().c_str(), args.c_str(), log.c_str());
    return;
  }
  if (!fs::exists(program))
    throw InputError(program.string() + ": benchmark program not found (configure with -DRFIDRAY_BUILD_BENCH=ON and "
                                        "build; `rfidray bench` runs the programs built beside it)");
  const std::string cmd = quoted(program.string()) + " " + args + " 2>&1 | tee " + quoted(log.string());
  std::printf("rfidray bench: %s %s\n", program.filename().c_str(), args.c_str());
  std::fflush(stdout);
  const auto t0 = std::chrono::steady_clock::now();
  // `set -o pipefail` so the program's own exit status survives the tee.
  const int status = std::system(("bash -c " + quoted("set -o pipefail; " + cmd)).c_str());
  if (status != 0) throw std::runtime_error(program.filename().string() + " failed (exit status " + std::to_string(status) + ")");
  std::printf("rfidray bench: %s done in %.0f s\n\n", program.filename().c_str(),
              std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

std::string machine() {
  std::ifstream in("/proc/cpuinfo");
  std::string line, model = "unknown CPU";
  while (std::getline(in, line))
    if (line.rfind("model name", 0) == 0) {
      model = line.substr(line.find(':') + 2);
      break;
    }
  return model + ", " + std::to_string(sysconf(_SC_NPROCESSORS_ONLN)) + " hardware threads";
}

// rays.json (Google Benchmark) → rays.csv and the ours/raw ratios per scene and thread count.
std::vector<std::string> ray_ratios(const fs::path& dir) {
  std::ifstream in(dir / "rays.json");
  std::stringstream text;
  text << in.rdbuf();
  // Google Benchmark writes NaN / inf for some aggregates (the cv of a counter that is always 0): not JSON.
  static const std::regex non_finite(R"(:\s*-?(nan|NaN|inf|Inf|infinity))");
  const nlohmann::json j = nlohmann::json::parse(std::regex_replace(text.str(), non_finite, ": null"));
  std::map<std::pair<std::string, int>, std::map<std::string, double>> rate;  // (scene, threads) → bench → rays/s
  std::map<std::string, double> triangles;
  std::ostringstream csv;  // rays.csv, written atomically below (io/atomic_file.h)
  csv << "benchmark,scene,threads,rays_per_s\n";
  std::vector<std::string> scenes;
  for (const auto& b : j.at("benchmarks")) {
    // Repetitions give aggregates: keep the median (plain runs have no aggregate_name).
    if (b.value("run_type", "") == "aggregate" && b.value("aggregate_name", "") != "median") continue;
    // name: "<bench>/<scene>/real_time/threads:<n>[_median]"
    const std::string name = b.at("name");
    const auto s1 = name.find('/'), s2 = name.find('/', s1 + 1);
    const std::string what = name.substr(0, s1), scene = name.substr(s1 + 1, s2 - s1 - 1);
    const int threads = std::stoi(name.substr(name.rfind(':') + 1));
    if (!b.contains("items_per_second") || !b.at("items_per_second").is_number()) continue;
    const double r = b.at("items_per_second");
    rate[{scene, threads}][what] = r;
    if (b.contains("triangles") && b.at("triangles").is_number()) triangles[scene] = b.at("triangles");
    csv << what << "," << scene << "," << threads << "," << r << "\n";
    if (std::find(scenes.begin(), scenes.end(), scene) == scenes.end()) scenes.push_back(scene);
  }
  io::write_file_atomic(dir / "rays.csv", [&](std::ostream& out) { out << csv.str(); }, "rays.csv");
  std::ostringstream ratio;  // rays_ratio.csv
  ratio << "scene,threads,occluded_ours_over_raw,intersect_ours_over_raw,occluded16_over_occluded1,raw_occluded1_rays_per_s,"
           "los_batch_over_fastest_raw\n";
  std::vector<std::string> lines;
  io::Series occ1{"occluded: ours / raw rtcOccluded1 (1 thread)", {}, {}, "linespoints"},
      occ2{"occluded: ours / raw rtcOccluded1 (2 threads)", {}, {}, "linespoints"},
      int2{"candidate search: ours / raw rtcIntersect1 (2 threads)", {}, {}, "linespoints"},
      p16{"raw rtcOccluded16 / rtcOccluded1 (2 threads)", {}, {}, "linespoints"};
  for (size_t si = 0; si < scenes.size(); ++si)
    for (int threads : {1, 2}) {
      auto& m = rate[{scenes[si], threads}];
      if (!m.count("occluded1_raw")) continue;
      const double occ = m["occluded1_ours"] / m["occluded1_raw"], inter = m["intersect1_ours"] / m["intersect1_raw"],
                   pk = m["occluded16_raw"] / m["occluded1_raw"];
      ratio << scenes[si] << "," << threads << "," << occ << "," << inter << "," << pk << "," << m["occluded1_raw"] << ",";
      // #13's figure: the per-pose LoS batch (los_ours, at the width timing chose) against the faster of the
      // raw single-ray and 16-ray packet loops; empty when bench_rays did not run it.
      if (m.count("los_ours") && m.count("occluded16_raw"))
        ratio << m["los_ours"] / std::max(m["occluded1_raw"], m["occluded16_raw"]);
      ratio << "\n";
      char buf[256];
      std::snprintf(buf, sizeof buf, "| %s | %d | %.2f | %.2f | %.2f | %.2f M |", scenes[si].c_str(), threads, occ,
                    inter, pk, m["occluded1_raw"] / 1e6);
      lines.push_back(buf);
      const double x = triangles[scenes[si]];
      io::Series& occ_series = threads == 1 ? occ1 : occ2;
      occ_series.x.push_back(x), occ_series.y.push_back(occ), occ_series.labels.push_back(threads == 1 ? scenes[si] : "");
      if (threads == 2) int2.x.push_back(x), int2.y.push_back(inter), p16.x.push_back(x), p16.y.push_back(pk);
    }
  io::write_file_atomic(dir / "rays_ratio.csv", [&](std::ostream& out) { out << ratio.str(); }, "rays_ratio.csv");
  io::write_png(dir / "rays_ratio.png", {io::Panel{"Ray throughput relative to a raw Embree loop on the same rays",
                                           "scene triangles", "ratio", {occ1, occ2, int2, p16}, true, false}});
  return lines;
}

int run_bench(const BenchOptions& o) {
  const fs::path dir = output_directory(o);
  const fs::path progs = bench_dir();
  const std::vector<std::string> programs{"bench_rays", "bench_sweep", "bench_accuracy", "localize_paper",
                                          "localize_sweeps", "localize_speed"};
  std::stringstream only(o.only);
  for (std::string item; std::getline(only, item, ',');)
    if (std::find(programs.begin(), programs.end(), item) == programs.end())
      throw InputError("option --only: unknown program '" + item +
                       "' (bench_rays, bench_sweep, bench_accuracy, localize_paper, localize_sweeps, localize_speed)");
  const auto wanted = [&](const std::string& name) {
    return o.only.empty() || ("," + o.only + ",").find("," + name + ",") != std::string::npos;
  };
  if (o.dry_run) std::printf("rfidray bench (dry run): results would go to %s\n", dir.c_str());
  else fs::create_directories(dir);
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<std::string> ratio_lines;
  if (wanted("bench_rays")) {
    const std::string args = std::string(o.quick ? "--scenes paper,w10k,w100k --benchmark_min_time=0.1 "
                                                 : "--benchmark_min_time=0.5 --benchmark_repetitions=3 "
                                                   "--benchmark_report_aggregates_only=true ") +
                             "--benchmark_out_format=json --benchmark_out=" + quoted((dir / "rays.json").string());
    run_program(progs / "bench_rays", args, dir / "bench_rays.log", o.dry_run);
    if (!o.dry_run) ratio_lines = ray_ratios(dir);
  }
  const std::string quick = o.quick ? " --quick" : "";
  if (wanted("bench_sweep")) run_program(progs / "bench_sweep", "--out " + quoted(dir.string()) + quick, dir / "bench_sweep.log", o.dry_run);
  if (wanted("bench_accuracy"))
    run_program(progs / "bench_accuracy", "--out " + quoted(dir.string()) + quick, dir / "bench_accuracy.log", o.dry_run);
  if (wanted("localize_paper")) {
    const std::string seeds = o.quick ? " --seeds 1" : " --seeds 5";
    run_program(progs / "localize_paper", "--out " + quoted((dir / "localize_paper_ideal").string()) + seeds,
                dir / "localize_paper_ideal.log", o.dry_run);
    run_program(progs / "localize_paper",
                "--channel single-bounce --model physical --out " +
                    quoted((dir / "localize_paper_multipath").string()) + seeds,
                dir / "localize_paper_multipath.log", o.dry_run);
  }
  if (wanted("localize_sweeps"))
    run_program(progs / "localize_sweeps", "--out " + quoted(dir.string()) + (o.quick ? " --trials 3" : ""),
                dir / "localize_sweeps.log", o.dry_run);
  if (wanted("localize_speed"))
    run_program(progs / "localize_speed", "--out " + quoted(dir.string()) + (o.quick ? " --repeats 3" : ""),
                dir / "localize_speed.log", o.dry_run);

  if (o.dry_run) return 0;
  std::ostringstream md;  // summary.md, written atomically below
  const std::time_t now = std::time(nullptr);
  char date[64];
  std::strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", std::gmtime(&now));
  md << "# rfidray bench" << (o.quick ? " --quick" : "") << "\n\nMachine: " << machine() << ". Date: " << date
     << ". Total " << static_cast<int>(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count())
     << " s.\n\n";
  if (!ratio_lines.empty()) {
    md << "## Ray throughput vs raw Embree (same rays, same process)\n\n"
       << "| scene | threads | occluded ours/raw | candidate search ours/raw | rtcOccluded16/rtcOccluded1 | raw rays/s |\n"
       << "|---|---|---|---|---|---|\n";
    for (const auto& l : ratio_lines) md << l << "\n";
    md << "\n";
  }
  md << "Logs of every program are beside this file (`*.log`); CSV and PNG files hold the figures.\n";
  io::write_file_atomic(dir / "summary.md", [&](std::ostream& out) { out << md.str(); }, "summary.md");
  std::printf("rfidray bench: results in %s (summary.md)\n", dir.c_str());
  return 0;
}

}  // namespace

std::function<int()> setup_bench(CLI::App& app) {
  auto opts = std::make_shared<BenchOptions>();
  CLI::App* cmd = app.add_subcommand("bench", "Run the speed and accuracy benchmarks; write CSV, PNG and summary.md");
  cmd->footer(
      "Runs the programs of bench/ built beside this rfidray (cmake -DRFIDRAY_BUILD_BENCH=ON, the default):\n"
      "  bench_rays       rays/s of our path finder vs a raw Embree loop on the same segments (ratio)\n"
      "  bench_sweep      links/s per channel level at 1 and 2 threads, vs triangles and vs tags; BVH build\n"
      "                   time and bytes per triangle\n"
      "  bench_accuracy   error vs time of each faster setting against the exhaustive image method, Pareto\n"
      "                   front, localization error it causes on the paper scenario\n"
      "  localize_paper   the paper's localization table (ideal channel and single-bounce multipath)\n"
      "  localize_sweeps  localization error and failure rate vs noise, sample spacing, aperture, distance\n"
      "  localize_speed   ms per tag per localization method, one thread, 1 000 and 4 000 reads\n"
      "The full run takes several minutes on 2 cores; --quick takes about a minute. Measure on an idle machine.");
  cmd->add_flag("--quick", opts->quick, "Smaller scenes, fewer runs and settings");
  cmd->add_option("-o,--output", opts->output_dir,
                  "Output directory (default: bench/results for a full run, out/bench-quick with --quick)");
  cmd->add_flag("--dry-run", opts->dry_run, "Print the output directory and the commands; run and write nothing");
  cmd->add_option("--only", opts->only,
                  "Comma-separated subset: bench_rays,bench_sweep,bench_accuracy,localize_paper,localize_sweeps");
  return [opts] { return run_bench(*opts); };
}

}  // namespace rfidray::cli
