// Accuracy against speed. Reference: the exhaustive image method keeping every path (single-bounce,
// candidates = exhaustive, no path dropped). Each faster setting — channel level, path-drop threshold, number
// and spread of per-pose candidate rays, facet-merging tolerance on a mesh with float noise — is timed on the
// same links and compared with the reference on what a reader reports:
//   phase error |wrap(arg h² − arg h_ref²)| and RSSI error |40 log10 |h|/|h_ref|| (p50 / p95 / max over the
//   links readable in either; core/channel_error.h), relative error of |h|, fraction of the reference's path
//   power (Σ|contribution|²) the setting misses, and, on the paper scenario (physical reader model, several
//   seeds), the localization error it causes (NLLS, tag height known, truth-side mirror prior).
//
// Second reference: `full` (double reflections and edge diffraction, core/utd.h) keeping every path. Every
// setting, and the levels above single-bounce (double-bounce, full-selective, full), is also compared with it
// (the *_vs_full columns). On w1m the levels above single-bounce cost 20–80 ms per link (full with the
// exhaustive candidate search ~1 s), so there they and the comparison with full run on the first
// --w1m-full-tags tags of each pose only (column links_vs_full), with the fast candidate search (the same paths
// as exhaustive, tests/raytrace/test_double_bounce.cpp).
//
//   bench_accuracy [--quick] [--out DIR] [--seeds N] [--runs N] [--w1m-full-tags N]
// Writes DIR/accuracy_<scene>.csv and DIR/accuracy_pareto.png (error vs time per link, Pareto front marked:
// per scene one panel against the single-bounce reference, one against full).
#include <omp.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>

#include "bench/localize_common.h"
#include "bench/workload.h"
#include "io/plot.h"
#include "io/scenario_yaml.h"
#include "core/channel_error.h"
#include "core/reader_model.h"
#include "raytrace/path_finder.h"
#include "raytrace/raytraced_channel.h"

using namespace rfidray;

namespace {

// A CSV field of an error or a localization figure: empty when not finite (an unbounded p95, a figure not computed).
std::string field(double v) { return error_text(v, 6, ""); }

struct Setting {
  std::string name;
  std::string group;  // level | drop | rays | spread | merge | level+ (above single-bounce)
  bool ideal = false;
  TraceOptions options;
  bool jittered = false;  // on the mesh with float noise
  FacetOptions facets;
  bool above_single_bounce() const { return group == "level+"; }
};

TraceOptions reference_options() {
  TraceOptions o;
  o.level = ChannelLevel::kSingleBounce;
  o.candidates = CandidateMode::kExhaustive;
  o.drop_below_db = 300.0;  // keep every path
  return o;
}

TraceOptions full_reference_options(CandidateMode candidates) {
  TraceOptions o;
  o.level = ChannelLevel::kFull;
  o.candidates = candidates;
  o.drop_below_db = 300.0;  // keep every path
  return o;
}

std::vector<Setting> settings(bool quick, bool with_merge) {
  std::vector<Setting> out;
  out.push_back({"ideal", "level", true, {}, false, {}});
  for (auto level : {ChannelLevel::kLos, ChannelLevel::kLosBlocked}) {
    TraceOptions o;
    o.level = level;
    out.push_back({to_string(level), "level", false, o, false, {}});
  }
  for (double drop : quick ? std::vector<double>{20, 40} : std::vector<double>{10, 20, 30, 40, 60}) {
    TraceOptions o;
    o.drop_below_db = drop;
    out.push_back({"drop " + std::to_string(int(drop)) + " dB", "drop", false, o, false, {}});
  }
  for (int rays : quick ? std::vector<int>{1024, 16384} : std::vector<int>{256, 1024, 4096, 16384, 65536}) {
    TraceOptions o;
    o.candidate_rays = rays;
    out.push_back({"rays " + std::to_string(rays), "rays", false, o, false, {}});
  }
  if (!quick)
    for (double spread : {0.5, 2.0}) {
      TraceOptions o;
      o.candidate_rays = 4096;
      o.candidate_spread = spread;
      char name[64];
      std::snprintf(name, sizeof name, "rays 4096 spread %.1f", spread);
      out.push_back({name, "spread", false, o, false, {}});
    }
  for (auto level : {ChannelLevel::kDoubleBounce, ChannelLevel::kFullSelective, ChannelLevel::kFull}) {
    TraceOptions o;
    o.level = level;
    out.push_back({to_string(level), "level+", false, o, false, {}});
  }
  if (with_merge)
    for (auto [dist, angle] : std::vector<std::pair<double, double>>{{1e-4, 1e-3}, {1e-3, 5e-3}, {5e-3, 2e-2}}) {
      FacetOptions f;
      f.distance_tolerance_m = dist;
      f.angle_tolerance_rad = angle;
      char name[96];
      std::snprintf(name, sizeof name, "noisy mesh, merge %.1f mm %.0f mrad", dist * 1e3, angle * 1e3);
      out.push_back({name, "merge", false, TraceOptions{}, true, f});
    }
  return out;
}

// Every vertex moved by up to ±0.5 mm (uniform, fixed seed): a mesh exported in float, or a scanned one.
std::vector<TriangleMesh> jittered(std::vector<TriangleMesh> meshes) {
  std::mt19937_64 rng(2040);
  std::uniform_real_distribution<double> u(-0.5e-3, 0.5e-3);
  for (TriangleMesh& m : meshes)
    for (Vec3& v : m.vertices) v += Vec3(u(rng), u(rng), u(rng));
  return meshes;
}

// The first `tags` tags of every pose (link a·tags + i), and the values of `all` (over w) on those links.
bench::Workload first_tags(const bench::Workload& w, size_t tags) {
  bench::Workload out = w;
  out.tags.resize(std::min(tags, w.tags.size()));
  return out;
}
std::vector<std::complex<double>> on_first_tags(const std::vector<std::complex<double>>& all, const bench::Workload& w,
                                                size_t tags) {
  std::vector<std::complex<double>> out;
  for (size_t a = 0; a < w.antennas.size(); ++a)
    for (size_t i = 0; i < std::min(tags, w.tags.size()); ++i) out.push_back(all[a * w.tags.size() + i]);
  return out;
}

struct LinkValues {
  std::vector<std::complex<double>> h;
  std::vector<double> path_power;  // Σ |contribution|² per link
  double us_per_link = 0.0;        // median over runs
};

LinkValues evaluate(const std::shared_ptr<const Scene>& scene, const Setting& s, const bench::Workload& w, int runs) {
  LinkValues v;
  v.h.resize(w.links());
  v.path_power.resize(w.links());
  const std::unique_ptr<Channel> channel = s.ideal ? std::unique_ptr<Channel>(std::make_unique<IdealChannel>())
                                                   : std::make_unique<RaytracedChannel>(scene, s.options);
  std::vector<double> times;
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    for (size_t a = 0; a < w.antennas.size(); ++a)
      channel->one_way(w.antennas[a], w.tags, 865.7e6,
                       std::span(v.h).subspan(a * w.tags.size(), w.tags.size()));
    times.push_back(std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count() /
                    double(w.links()));
  }
  std::sort(times.begin(), times.end());
  v.us_per_link = times[times.size() / 2];
  // Path powers (untimed).
  if (s.ideal) {
    for (size_t i = 0; i < v.h.size(); ++i) v.path_power[i] = std::norm(v.h[i]);
    return v;
  }
  const PathFinder finder(scene, s.options);
  for (size_t a = 0; a < w.antennas.size(); ++a) {
    PoseCandidates c;
    finder.prepare_pose(w.antennas[a].pose.position, c);
#pragma omp parallel for schedule(dynamic, 16)
    for (size_t i = 0; i < w.tags.size(); ++i) {
      std::vector<TracedPath> paths;
      finder.trace(w.antennas[a], w.tags[i], 865.7e6, c, paths);
      double p = 0.0;
      for (const TracedPath& t : paths) p += std::norm(t.contribution);
      v.path_power[a * w.tags.size() + i] = p;
    }
  }
  return v;
}

struct LocalizationError {
  double mean_mm = 0.0, max_mm = 0.0;
  int ok = 0, failed = 0;
};

// The paper scenario with every antenna on the physical model, simulated with `channel`, the mobile antenna's
// tags localized (NLLS, height known, truth-side prior) over `seeds` seeds.
LocalizationError localization_error(const Scenario& base, const Channel& channel, int seeds) {
  LocalizationError e;
  double sum = 0.0;
  size_t mobile = 0;
  for (size_t i = 0; i < base.antennas.size(); ++i)
    if (base.antennas[i].reader.name == "mobile") mobile = i;
  for (int s = 0; s < seeds; ++s) {
    Scenario scenario = base;
    scenario.seed = 1 + static_cast<uint64_t>(s);
    const SimulationResult sim = simulate(scenario, channel);
    const auto tags = bench::tag_reads(scenario, scenario.antennas[mobile], sim.antennas[mobile]);
    for (size_t t = 0; t < tags.size(); ++t) {
      const Vec3 truth = scenario.tags[t].motion.pose.position;
      loc::LocalizeOptions o;
      o.height_known = true;
      o.tag_height_m = truth.z();
      o.mirror_prior = loc::MirrorPrior::kPoint;
      o.prior_point = truth;
      const loc::LocalizeResult r = tags[t].read_count() ? loc::localize(loc::Method::kNlls, tags[t], o)
                                                         : loc::LocalizeResult{};
      if (!r.ok) {
        ++e.failed;
        continue;
      }
      const double err = 1000.0 * (r.position - truth).norm();
      sum += err;
      e.max_mm = std::max(e.max_mm, err);
      ++e.ok;
    }
  }
  e.mean_mm = e.ok ? sum / e.ok : std::numeric_limits<double>::quiet_NaN();
  return e;
}

// A CSV field in double quotes (setting names contain commas).
std::string quoted(const std::string& s) { return "\"" + s + "\""; }

// Indices of the points not dominated in (time, error), sorted by time.
std::vector<size_t> pareto_front(const std::vector<double>& time, const std::vector<double>& error) {
  std::vector<size_t> idx(time.size());
  for (size_t i = 0; i < idx.size(); ++i) idx[i] = i;
  std::sort(idx.begin(), idx.end(), [&](size_t a, size_t b) { return std::tie(time[a], error[a]) < std::tie(time[b], error[b]); });
  std::vector<size_t> front;
  double best = std::numeric_limits<double>::infinity();
  for (size_t i : idx)
    if (error[i] < best) front.push_back(i), best = error[i];
  return front;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Accuracy vs speed of the channel settings against the exhaustive image method and against full"};
  bool quick = false;
  std::string out_dir = "bench/results";
  int seeds = 3, runs = 3, w1m_full_tags = 25;
  app.add_flag("--quick", quick, "fewer settings, links and seeds");
  app.add_option("--out", out_dir, "output directory")->capture_default_str();
  app.add_option("--seeds", seeds, "seeds of the localization runs")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--runs", runs, "timing runs (median)")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--w1m-full-tags", w1m_full_tags, "w1m: tags per pose of the levels above single-bounce and of the comparison with full")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  CLI11_PARSE(app, argc, argv);
  if (quick) seeds = 1, runs = std::min(runs, 2);
  std::filesystem::create_directories(out_dir);

  Scenario paper = io::load_scenario(std::string(RFIDRAY_SOURCE_DIR) + "/scenes/paper_warehouse.yaml");
  for (AntennaSpec& a : paper.antennas) a.reader.model = ReaderModelKind::kPhysical;
  const double min_h2 = min_readable_h2(ReaderParams{}, TagParams{});

  struct SceneCase {
    std::string name;
    bench::BenchScene scene;
    int tags, poses;
    bool localize;
    size_t full_tags;             // tags per pose of the comparison with full
    CandidateMode full_candidates;  // of the full reference
  };
  std::vector<SceneCase> cases{{"paper", bench::find_bench_scene("paper"), quick ? 60 : 200, quick ? 8 : 20, true,
                                size_t(quick ? 60 : 200), CandidateMode::kExhaustive}};
  if (!quick) cases.push_back({"w1m", bench::find_bench_scene("w1m"), 250, 4, false, size_t(w1m_full_tags), CandidateMode::kExact});

  std::vector<io::Panel> panels;
  for (const SceneCase& sc : cases) {
    const std::vector<TriangleMesh> meshes = bench::scene_meshes(sc.scene);
    const auto clean = std::make_shared<const Scene>(meshes, MaterialAssignment{});
    const bench::Workload w = bench::scene_workload(sc.scene, sc.tags, sc.poses);
    const bench::Workload ws = first_tags(w, sc.full_tags);  // the links compared with full
    Setting ref{"reference (exhaustive, all paths)", "reference", false, reference_options(), false, {}};
    const LinkValues reference = evaluate(clean, ref, w, runs);
    const std::vector<std::complex<double>> reference_sub = on_first_tags(reference.h, w, sc.full_tags);
    double ref_power = 0.0;
    for (double p : reference.path_power) ref_power += p;
    const std::vector<double> min_h2s(w.links(), min_h2), min_h2_sub(ws.links(), min_h2);
    LocalizationError ref_loc;
    if (sc.localize) ref_loc = localization_error(paper, RaytracedChannel(clean, ref.options), seeds);
    Setting full_ref{std::string("full reference (") + to_string(sc.full_candidates) + " candidates, all paths)",
                     "reference-full", false, full_reference_options(sc.full_candidates), false, {}};
    const LinkValues full = evaluate(clean, full_ref, ws, 1);
    const ChannelErrorStats full_self = channel_errors(full.h, full.h, min_h2_sub);

    std::ofstream csv(std::filesystem::path(out_dir) / ("accuracy_" + sc.name + ".csv"));
    csv << "scene,setting,group,links,us_per_link,speedup,phase_p50_rad,phase_p95_rad,phase_max_rad,rssi_p50_db,"
           "rssi_p95_db,magnitude_p95,phase_p95_both_rad,rssi_p95_both_db,missed_power_fraction,mismatches,"
           "readable_links,loc_mean_mm,loc_max_mm,loc_failed,links_vs_full,phase_p95_vs_full_rad,"
           "rssi_p95_vs_full_db,phase_p95_both_vs_full_rad,rssi_p95_both_vs_full_db,mismatches_vs_full,"
           "readable_links_vs_full\n";
    std::printf("%s: %zu triangles, %zu links (%zu tags x %zu poses); reference %.2f us/link", sc.name.c_str(),
                clean->triangle_count(), w.links(), w.tags.size(), w.antennas.size(), reference.us_per_link);
    if (sc.localize) std::printf(", localization %.1f mm mean (%d tags x seeds)", ref_loc.mean_mm, ref_loc.ok);
    std::printf("\n  full reference (%s candidates, all paths): %zu links (first %zu tags x %zu poses), %.1f us/link, "
                "%zu readable\n",
                to_string(sc.full_candidates), ws.links(), ws.tags.size(), ws.antennas.size(), full.us_per_link,
                full_self.links);
    std::printf("  %-36s %9s %8s %10s %10s %10s %9s %8s %9s | vs full: %9s %9s %9s %6s\n", "setting", "us/link",
                "speedup", "phase p50", "phase p95", "RSSI p95", "missed", "mismatch", "loc mm", "phase p95",
                "(both)", "RSSI p95", "flips");
    auto vs_full_columns = [&](const ChannelErrorStats& e) {
      std::ostringstream o;
      o << ws.links() << "," << field(e.phase_p95_rad) << "," << field(e.rssi_p95_db) << ","
        << field(e.phase_p95_both_rad) << "," << field(e.rssi_p95_both_db) << "," << e.status_mismatches << "," << e.links;
      return o.str();
    };
    const ChannelErrorStats ref_vs_full = channel_errors(full.h, reference_sub, min_h2_sub);
    csv << sc.name << "," << quoted(ref.name) << ",reference," << w.links() << "," << reference.us_per_link
        << ",1,0,0,0,0,0,0,0,0,0,0," << channel_errors(reference.h, reference.h, min_h2s).links << ","
        << (sc.localize ? ref_loc.mean_mm : NAN) << ","
        << (sc.localize ? ref_loc.max_mm : NAN) << "," << ref_loc.failed << "," << vs_full_columns(ref_vs_full) << "\n";
    csv << sc.name << "," << quoted(full_ref.name) << ",reference-full," << ws.links() << "," << full.us_per_link << ","
        << reference.us_per_link / full.us_per_link << ",,,,,,,,,,,,,,," << vs_full_columns(full_self) << "\n";

    // Two charts per scene: the settings of the single-bounce search against its exhaustive reference, and
    // everything against full (the levels above single-bounce timed on the links compared with full).
    // Points are drawn at the p95 over the links readable in both; only settings whose p95 with flips counted
    // as infinite error is finite (≤ 5 % of the links flip) can be on the Pareto front.
    auto front_error = [](const ChannelErrorStats& e) {
      return std::isfinite(e.phase_p95_rad) ? e.phase_p95_both_rad : std::numeric_limits<double>::infinity();
    };
    std::vector<double> times{reference.us_per_link}, errors{0.0}, front_errors{0.0};
    std::vector<std::string> labels{"reference"};
    std::vector<double> times_full{reference.us_per_link, full.us_per_link},
        errors_full{ref_vs_full.phase_p95_both_rad, 0.0}, front_errors_full{front_error(ref_vs_full), 0.0};
    std::vector<std::string> labels_full{
        "single-bounce exhaustive, all paths (" + std::to_string(ref_vs_full.status_mismatches) + " flips)",
        "full (reference)"};
    for (const Setting& s : settings(quick, sc.localize)) {
      std::shared_ptr<const Scene> scene = clean;
      if (s.jittered) {
        SceneOptions so;
        so.facets = s.facets;
        scene = std::make_shared<const Scene>(jittered(meshes), MaterialAssignment{}, so);
      }
      // Levels above single-bounce run on the links compared with full only (all of them on the paper).
      const bool sub = s.above_single_bounce();
      const bench::Workload& wl = sub ? ws : w;
      const LinkValues v = evaluate(scene, s, wl, runs);
      const ChannelErrorStats e = channel_errors(sub ? reference_sub : reference.h, v.h, sub ? min_h2_sub : min_h2s);
      const ChannelErrorStats ef = channel_errors(full.h, sub ? v.h : on_first_tags(v.h, w, sc.full_tags), min_h2_sub);
      double power = 0.0, ref_power_here = sub ? 0.0 : ref_power;
      for (double p : v.path_power) power += p;
      if (sub)
        for (size_t a = 0; a < w.antennas.size(); ++a)
          for (size_t i = 0; i < ws.tags.size(); ++i) ref_power_here += reference.path_power[a * w.tags.size() + i];
      const double missed = std::max(0.0, (ref_power_here - power) / ref_power_here);
      LocalizationError le{NAN, NAN, 0, 0};
      // (Not for the levels above single-bounce: the paper scenario's ~20 k links per seed at ~1 ms each.)
      if (sc.localize && !sub) {
        const std::unique_ptr<Channel> ch = s.ideal ? std::unique_ptr<Channel>(std::make_unique<IdealChannel>())
                                                    : std::make_unique<RaytracedChannel>(scene, s.options);
        le = localization_error(paper, *ch, seeds);
      }
      std::printf("  %-36s %9.2f %8.1f %10s %10s %10s %9.2e %8zu %9s | %18s %9s %9s %6zu\n", s.name.c_str(),
                  v.us_per_link, reference.us_per_link / v.us_per_link, error_text(e.phase_p50_rad, 4, "flips").c_str(),
                  error_text(e.phase_p95_rad, 4, "flips").c_str(), error_text(e.rssi_p95_db, 4, "flips").c_str(), missed,
                  e.status_mismatches, error_text(le.mean_mm, 4, "-").c_str(), error_text(ef.phase_p95_rad, 4, "flips").c_str(),
                  error_text(ef.phase_p95_both_rad, 4, "flips").c_str(), error_text(ef.rssi_p95_db, 4, "flips").c_str(),
                  ef.status_mismatches);
      csv << sc.name << "," << quoted(s.name) << "," << s.group << "," << wl.links() << "," << v.us_per_link << ","
          << reference.us_per_link / v.us_per_link << "," << field(e.phase_p50_rad) << "," << field(e.phase_p95_rad) << ","
          << field(e.phase_max_rad) << "," << field(e.rssi_p50_db) << "," << field(e.rssi_p95_db) << ","
          << field(e.magnitude_p95) << "," << field(e.phase_p95_both_rad) << "," << field(e.rssi_p95_both_db) << ","
          << missed << "," << e.status_mismatches << "," << e.links << "," << field(le.mean_mm) << ","
          << field(le.max_mm) << "," << le.failed << "," << vs_full_columns(ef)
          << "\n";
      if (!sub) {
        times.push_back(v.us_per_link);
        errors.push_back(e.phase_p95_both_rad);
        front_errors.push_back(front_error(e));
        labels.push_back(s.name);
      }
      // (A setting with no link readable in both has no phase error to draw: left out of the chart.)
      if (!s.jittered && ef.links > ef.status_mismatches) {
        times_full.push_back(v.us_per_link);
        errors_full.push_back(ef.phase_p95_both_rad);
        front_errors_full.push_back(front_error(ef));
        labels_full.push_back(s.name + " (" + std::to_string(ef.status_mismatches) + " flips)");
      }
    }
    // Chart: error vs time, one point per setting (errors of 0 drawn at 1e-6 on the log axis).
    auto chart = [&](const std::vector<double>& t, const std::vector<double>& err, const std::vector<double>& front_err,
                     const std::vector<std::string>& lab, const std::string& title) {
      io::Series pts{"settings", {}, {}, "points pt 7 ps 1.2"};
      for (size_t i = 0; i < t.size(); ++i)
        pts.x.push_back(t[i]), pts.y.push_back(std::max(err[i], 1e-6)), pts.labels.push_back(lab[i]);
      io::Series front{"Pareto front", {}, {}, "linespoints lw 2"};
      for (size_t i : pareto_front(t, front_err)) front.x.push_back(t[i]), front.y.push_back(std::max(err[i], 1e-6));
      panels.push_back({title, "time per link (us, all threads)", "p95 phase error (rad)", {pts, front}, true, true});
    };
    chart(times, errors, front_errors, labels,
          sc.name + ": p95 round-trip phase error (links readable in both) vs time per link; reference: single-bounce exhaustive, "
                    "all paths; front: settings with <= 5 % flips");
    char title[256];
    std::snprintf(title, sizeof title,
                  "%s: the same against full (double reflections + UTD diffraction, all paths), %zu links (%zu tags x %zu "
                  "poses); flips: links readable in one only; front: settings with <= 5 %% flips",
                  sc.name.c_str(), ws.links(), ws.tags.size(), ws.antennas.size());
    chart(times_full, errors_full, front_errors_full, labels_full, title);
  }
  try {
    io::write_png(std::filesystem::path(out_dir) / "accuracy_pareto.png", panels, 1200, 520);
  } catch (const std::exception& e) {
    std::cerr << "bench_accuracy: chart not written: " << e.what() << "\n";
  }
  std::printf("wrote %s/accuracy_*.csv and accuracy_pareto.png\n", out_dir.c_str());
  return 0;
}
