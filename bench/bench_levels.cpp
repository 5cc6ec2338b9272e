// Cost and accuracy of every traced channel level, up to double-bounce and full (edge diffraction), on one
// workload: links/s at 1 and 2 threads (median of runs, `one_way` per antenna pose as `simulate` calls it),
// rays per link, and the errors of what a reader reports against `full` with the exhaustive candidate search
// (core/channel_error.h: p95 round-trip phase and RSSI errors over links readable in either, read flips).
//
//   bench_levels [--out DIR] [--runs N] [--tags N] [--poses N] [--scenes paper,w10k,w100k,w1m] [--reference LEVEL]
//                [--reference-candidates exhaustive|exact] [--skipped-fractions 0.02,0.1] [--posts-as-faces] [--first-order-too]
// (--reference double-bounce: what double reflections alone add, without diffraction. --reference-candidates
// fast: the same paths, for scenes where the exhaustive search is too slow (w1m: ~1 s per link at full).
// --skipped-fractions: full-selective once per ε, TraceOptions::diffraction_skipped_fraction. --posts-as-faces: also
// full-selective and full with thin posts as faces and edges (TraceOptions::thin_post_max_width_m = 0), as before
// they were cylinders: what the post model costs and how much it changes a link, in the same run.)
// --first-order-too: also full-selective and full without second-order diffraction (double_diffraction_max_m = 0).
// Writes DIR/levels.csv and DIR/levels_pareto.png (error against µs per link).
#include <omp.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "bench/pool_counters.h"
#include "bench/workload.h"
#include "core/channel_error.h"
#include "core/reader_model.h"
#include "io/plot.h"
#include "raytrace/raytraced_channel.h"

using namespace rfidray;
using bench::take_pool_rays;
using bench::take_pool_plane_pairs;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<std::complex<double>> values(const Channel& ch, const bench::Workload& w) {
  std::vector<std::complex<double>> all, h(w.tags.size());
  for (const Endpoint& ant : w.antennas) {
    ch.one_way(ant, w.tags, 865.7e6, h);
    all.insert(all.end(), h.begin(), h.end());
  }
  return all;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Links/s and accuracy (against full, exhaustive) of every traced channel level"};
  std::string out_dir = "bench/results", scene_list = "paper", reference_level = "full";
  std::string reference_candidates = "exhaustive", fractions_list = "0.02";
  int runs = 5, tags = 1000, poses = 8;
  app.add_option("--out", out_dir, "output directory")->capture_default_str();
  app.add_option("--runs", runs, "runs per measurement (median reported)")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--tags", tags, "tags per antenna pose")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--poses", poses, "antenna poses")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--scenes", scene_list, "comma-separated subset of paper,w10k,w100k,w1m")->capture_default_str();
  app.add_option("--reference", reference_level, "reference level (exhaustive candidates)")->capture_default_str();
  app.add_option("--reference-candidates", reference_candidates, "candidate search of the reference: exhaustive | exact")
      ->capture_default_str();
  bool posts_as_faces = false;
  app.add_flag("--posts-as-faces", posts_as_faces, "also full-selective and full with thin posts as faces and edges");
  bool first_order_too = false;
  app.add_flag("--first-order-too", first_order_too,
               "also full-selective and full with first-order diffraction only (double_diffraction_max_m = 0)");
  app.add_option("--skipped-fractions", fractions_list,
                 "full-selective: skipped fractions ε of |h| (TraceOptions::diffraction_skipped_fraction), comma-separated")
      ->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  std::vector<double> fractions;
  CandidateMode ref_candidates = CandidateMode::kExhaustive;
  try {
    ref_candidates = parse_candidate_mode(reference_candidates, "--reference-candidates");
    for (const std::string& z : bench::split_commas(fractions_list)) {
      fractions.push_back(std::stod(z));
      if (!(fractions.back() >= 0.0 && fractions.back() < 1.0))
        throw std::invalid_argument("--skipped-fractions: each ε must be in [0, 1), got " + z);
    }
  } catch (const std::exception& e) {
    std::cerr << "bench_levels: " << e.what() << "\n";
    return 2;
  }
  std::filesystem::create_directories(out_dir);
  const auto reference_parsed = parse_channel_level(std::string_view(reference_level));
  if (!reference_parsed || !is_traced(*reference_parsed)) {
    std::cerr << "bench_levels: --reference must be a traced level\n";
    return 2;
  }
  std::vector<bench::BenchScene> scenes;
  try {
    for (const std::string& n : bench::split_commas(scene_list)) scenes.push_back(bench::find_bench_scene(n));
  } catch (const std::exception& e) {
    std::cerr << "bench_levels: " << e.what() << "\n";
    return 2;
  }
  // The rows: every traced level, full-selective once per zone count.
  std::vector<std::pair<std::string, TraceOptions>> rows;
  for (ChannelLevel level : {ChannelLevel::kLos, ChannelLevel::kLosBlocked, ChannelLevel::kSingleBounce,
                             ChannelLevel::kDoubleBounce, ChannelLevel::kFullSelective, ChannelLevel::kFull}) {
    if (static_cast<int>(level) > static_cast<int>(*reference_parsed)) continue;
    TraceOptions o;
    o.level = level;
    if (level == ChannelLevel::kDoubleBounce) {  // the plane pairs shared per block of tags, and not (same paths)
      TraceOptions never = o;
      never.plane_pair_sharing = TraceOptions::Sharing::kNever;
      rows.emplace_back("double-bounce unshared", never);
    }
    const auto with_faces = [&](const std::string& label, TraceOptions t) {
      rows.emplace_back(label, t);
      if (!includes(level, ChannelLevel::kFullSelective)) return;
      if (first_order_too) {
        TraceOptions first = t;
        first.double_diffraction_max_m = 0.0;
        rows.emplace_back(label + " first order", first);
      }
      if (!posts_as_faces) return;
      t.thin_post_max_width_m = 0.0;
      rows.emplace_back(label + " posts as faces", t);
    };
    if (level != ChannelLevel::kFullSelective) {
      with_faces(to_string(level), o);
      continue;
    }
    for (double eps : fractions) {
      o.diffraction_skipped_fraction = eps;
      char label[64];
      std::snprintf(label, sizeof label, "full-selective e=%g", eps);
      with_faces(label, o);
    }
  }
  std::ofstream csv(std::filesystem::path(out_dir) / "levels.csv");
  csv << "scene,triangles,edges,level,threads,links,links_per_s_median,us_per_link,rays_per_link,plane_pairs_per_link,"
         "readable,read_flips,phase_p95_rad,rssi_p95_db,phase_p95_both_rad,rssi_p95_both_db\n";
  std::vector<io::Series> phase_series, rssi_series;
  for (const bench::BenchScene& bs : scenes) {
    const auto scene = std::make_shared<const Scene>(bench::scene_meshes(bs), MaterialAssignment{});
    const bench::Workload w = bench::scene_workload(bs, tags, poses);
    TraceOptions ref_options;
    ref_options.level = *reference_parsed;
    ref_options.candidates = ref_candidates;
    const RaytracedChannel reference(scene, ref_options);
    omp_set_num_threads(2);
    const auto t_ref = std::chrono::steady_clock::now();
    const auto ref = values(reference, w);
    std::printf("%s: %zu triangles, %zu planes, %zu edges; %zu tags x %zu poses; reference (%s %s) %.1f µs/link\n",
                bs.name.c_str(), scene->triangle_count(), reference.finder().plane_count(),
                reference.finder().edges().size(), w.tags.size(),
                w.antennas.size(), reference_level.c_str(), to_string(ref_candidates), 1e6 * seconds_since(t_ref) / double(w.links()));
    const std::vector<double> min_h2(ref.size(), min_readable_h2(ReaderParams{}, TagParams{}));
    io::Series ph{bs.name + " phase p95 (rad)", {}, {}, "linespoints", {}};
    io::Series rs{bs.name + " RSSI p95 (dB)", {}, {}, "linespoints", {}};
    for (const auto& [label, o] : rows) {
      const RaytracedChannel ch(scene, o);
      const ChannelErrorStats e = channel_errors(ref, values(ch, w), min_h2);
      for (int threads : {1, 2}) {
        omp_set_num_threads(threads);
        std::vector<double> rates;
        take_pool_rays();
        take_pool_plane_pairs();
        std::vector<std::complex<double>> h(w.tags.size());
        for (int r = 0; r < runs; ++r) {
          const auto t0 = std::chrono::steady_clock::now();
          for (const Endpoint& ant : w.antennas) ch.one_way(ant, w.tags, 865.7e6, h);
          rates.push_back(double(w.links()) / seconds_since(t0));
        }
        const double rays = double(take_pool_rays()) / double(runs * w.links());
        const double pairs = double(take_pool_plane_pairs()) / double(runs * w.links());
        std::sort(rates.begin(), rates.end());
        const double median = rates[rates.size() / 2];
        // A p95 that flips reach is unbounded: "flips" in the table, an empty field in the CSV.
        std::printf("  %-22s %d thread%s %11.0f links/s %8.2f µs/link %8.1f rays/link %8.0f plane pairs/link | readable %zu, "
                    "flips %zu, phase p95 %s rad, RSSI p95 %s dB (readable in both: %.4g rad, %.4g dB)\n",
                    label.c_str(), threads, threads == 1 ? " " : "s", median, 1e6 / median, rays, pairs, e.links,
                    e.status_mismatches, error_text(e.phase_p95_rad, 4, "(flips)").c_str(),
                    error_text(e.rssi_p95_db, 4, "(flips)").c_str(), e.phase_p95_both_rad, e.rssi_p95_both_db);
        csv << bs.name << "," << scene->triangle_count() << "," << reference.finder().edges().size() << ","
            << label << "," << threads << "," << w.links() << "," << median << "," << 1e6 / median << ","
            << rays << "," << pairs << "," << e.links << "," << e.status_mismatches << ","
            << error_text(e.phase_p95_rad, 6, "") << "," << error_text(e.rssi_p95_db, 6, "") << ","
            << error_text(e.phase_p95_both_rad, 6, "") << "," << error_text(e.rssi_p95_both_db, 6, "") << "\n";
        if (threads == 1) {
          // Links readable in only one channel make the p95 infinite: the chart shows the p95 over links
          // readable in both (the table above has the flips).
          ph.x.push_back(1e6 / median), ph.y.push_back(std::max(e.phase_p95_both_rad, 1e-4));
          rs.x.push_back(1e6 / median), rs.y.push_back(std::max(e.rssi_p95_both_db, 1e-3));
          ph.labels.push_back(label);
          rs.labels.push_back(label);
        }
      }
    }
    phase_series.push_back(ph);
    rssi_series.push_back(rs);
  }
  try {
    io::write_png(std::filesystem::path(out_dir) / "levels_pareto.png",
                  {{"Round-trip phase error vs cost, against full (exhaustive); links readable in both", "µs per link (1 thread)",
                    "phase p95 (rad)", phase_series, true, true},
                   {"RSSI error vs cost, against full (exhaustive)", "µs per link (1 thread)", "RSSI p95 (dB)",
                    rssi_series, true, true}});
  } catch (const std::exception& e) {
    std::cerr << "bench_levels: chart not written: " << e.what() << "\n";
  }
  std::printf("wrote %s/levels.csv, levels_pareto.png\n", out_dir.c_str());
  return 0;
}
