// Links per second of the ray-traced channel, as `rfidray simulate` computes them: for every antenna pose one
// Channel::one_way call over all tags (the batch shares the pose's candidate search), OpenMP over tags.
//
//   per scene (paper warehouse, parametric warehouses at ~10 k … 5 M triangles): scene + BVH build time,
//   Embree bytes and resident bytes per triangle; then per channel level (los, los+blocked, single-bounce exact,
//   single-bounce with 4096 candidate rays) and thread count (1, 2): median links/s over runs, rays per link;
//   on the 1 M-triangle warehouse also links/s vs number of tags (100 … 100 k).
//
//   bench_sweep [--quick] [--out DIR] [--runs N] [--tags N] [--poses N] [--scenes a,b,...] [--settings a,b,...]
//               [--threads 1 2 ...] [--no-tags-sweep]
// rays_per_link counts every Embree query (rtcIntersect1 / rtcOccluded1, one per active lane of a packet)
// issued, per link: a figure that does not depend on the machine. Each measurement first traces one untimed
// pose (the channel's one-off packet-width timing at level los, cold caches); the level-los lines say which
// packet width the channel chose.
// culled_per_link: reflection candidates rejected without a ray because a leg crosses a covered rectangle
// (raytrace/covered_rects.h), with setting "single-bounce cull" (TraceOptions::cull_covered; off by default; run
// only when --settings names it).
// mirror_points_per_link: single-reflection image points that lie on a facet, each needing a visibility
// decision (a leg's ray, or culling); reflections_per_link: those with both legs clear (paths). Without
// culling an exact search spends at least one ray on each mirror point and two on each reflection, so
// rays_per_link ≥ 1 (the direct path) + mirror_points_per_link + reflections_per_link at level single-bounce.
// Writes DIR/links_per_level.csv, DIR/links_vs_tags.csv, DIR/links_vs_triangles.png, DIR/links_vs_tags.png.
#include <omp.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "bench/pool_counters.h"
#include "bench/workload.h"
#include "io/plot.h"
#include "raytrace/raytraced_channel.h"

using namespace rfidray;
using bench::take_pool_rays;
using bench::take_pool_culled;
using bench::take_pool_mirror_points;
using bench::take_pool_reflections;

namespace {

struct Setting {
  std::string name;
  TraceOptions options;
  bool only_if_named = false;  // not part of the default run (--settings must name it)
};

std::vector<Setting> settings() {
  std::vector<Setting> out;
  auto add = [&](std::string name, ChannelLevel level, int rays) {
    TraceOptions o;
    o.level = level;
    o.candidate_rays = rays;
    out.push_back({std::move(name), o});
  };
  add("los", ChannelLevel::kLos, 0);
  // The opt-in packets (TraceOptions::los_packets_by_timing; not the default: determinism).
  add("los packets", ChannelLevel::kLos, 0);
  out.back().options.los_packets_by_timing = true;
  add("los+blocked", ChannelLevel::kLosBlocked, 0);
  add("single-bounce", ChannelLevel::kSingleBounce, 0);
  // The same with the covered-rectangle culling of reflection legs (TraceOptions::cull_covered, off by default).
  add("single-bounce cull", ChannelLevel::kSingleBounce, 0);
  out.back().options.cull_covered = true;
  out.back().only_if_named = true;  // an A/B setting: the default run's tables and charts stay as they were
  add("single-bounce rays=4096", ChannelLevel::kSingleBounce, 4096);
  return out;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Resident set size of this process (bytes), from /proc/self/statm.
size_t resident_bytes() {
  std::ifstream in("/proc/self/statm");
  size_t pages = 0, resident = 0;
  in >> pages >> resident;
  return resident * 4096;
}

// ", packets of 16" when the channel traces its level-los rays in packets (chosen by measurement).
std::string packet_note(const RaytracedChannel& ch) {
  const int w = ch.los_packet_width();
  return w > 1 ? ", packets of " + std::to_string(w) : w == 1 ? ", single rays" : "";
}

struct Rate {
  double median = 0, min = 0, max = 0, rays_per_link = 0, culled_per_link = 0, mirror_points_per_link = 0,
         reflections_per_link = 0;
};

Rate measure(const RaytracedChannel& ch, const bench::Workload& w, int runs) {
  std::vector<std::complex<double>> h(w.tags.size());
  std::vector<double> rates;
  // One untimed pose first: the channel's one-off work (level los times its packet widths on its first
  // pose) and cold caches are not part of the rate.
  ch.one_way(w.antennas.front(), w.tags, 865.7e6, h);
  take_pool_rays();
  take_pool_culled();
  take_pool_mirror_points();
  take_pool_reflections();
  for (int r = 0; r < runs; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    for (const Endpoint& ant : w.antennas) ch.one_way(ant, w.tags, 865.7e6, h);
    rates.push_back(double(w.links()) / seconds_since(t0));
  }
  const uint64_t rays = take_pool_rays(), culled = take_pool_culled();
  const uint64_t points = take_pool_mirror_points(), found = take_pool_reflections();
  std::sort(rates.begin(), rates.end());
  const double links = double(runs) * double(w.links());
  return {rates[rates.size() / 2], rates.front(), rates.back(), double(rays) / links, double(culled) / links,
          double(points) / links, double(found) / links};
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Links/s of the ray-traced channel per level, thread count, scene size and tag count"};
  bool quick = false;
  std::string out_dir = "bench/results", scene_list;
  int runs = 5, tags = 10000, poses = 4;
  app.add_flag("--quick", quick, "small run: scenes up to 1 M triangles, fewer tags and runs");
  app.add_option("--out", out_dir, "output directory")->capture_default_str();
  app.add_option("--runs", runs, "runs per measurement (median reported)")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--tags", tags, "tags per antenna pose")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--poses", poses, "antenna poses per run")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--scenes", scene_list, "comma-separated subset of paper,w10k,w100k,w1m,w5m");
  std::string setting_list;
  app.add_option("--settings", setting_list, "comma-separated subset of the settings (los, 'los packets', "
                                             "los+blocked, single-bounce, 'single-bounce cull', 'single-bounce rays=4096')");
  bool no_tags_sweep = false;
  app.add_flag("--no-tags-sweep", no_tags_sweep, "skip the links/s vs tags sweep on w1m");
  std::vector<int> thread_counts{1, 2};
  app.add_option("--threads", thread_counts, "thread counts")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  std::vector<Setting> chosen;
  for (const Setting& st : settings())
    if (setting_list.empty() ? !st.only_if_named : ("," + setting_list + ",").find("," + st.name + ",") != std::string::npos)
      chosen.push_back(st);
  if (chosen.empty()) {
    std::cerr << "bench_sweep: --settings: no known setting in '" << setting_list << "'\n";
    return 2;
  }
  if (quick) runs = std::min(runs, 3), tags = std::min(tags, 2000);
  std::filesystem::create_directories(out_dir);

  std::vector<bench::BenchScene> scenes;
  try {
    if (!scene_list.empty())
      for (const std::string& n : bench::split_commas(scene_list)) scenes.push_back(bench::find_bench_scene(n));
    else
      for (const bench::BenchScene& s : bench::bench_scenes())
        if (!quick || s.name != "w5m") scenes.push_back(s);
  } catch (const std::exception& e) {
    std::cerr << "bench_sweep: " << e.what() << "\n";
    return 2;
  }

  std::ofstream csv(std::filesystem::path(out_dir) / "links_per_level.csv");
  csv << "scene,triangles,facets,planes,build_s,embree_bytes_per_triangle,resident_bytes_per_triangle,setting,"
         "threads,tags,poses,links_per_s_median,links_per_s_min,links_per_s_max,rays_per_link,culled_per_link,"
         "covered_bytes_per_triangle,covered_build_s,mirror_points_per_link,reflections_per_link\n";
  std::map<std::string, io::Series> by_triangles;  // setting → (triangles, links/s at 2 threads)
  std::ofstream tags_csv(std::filesystem::path(out_dir) / "links_vs_tags.csv");
  tags_csv << "scene,setting,threads,tags,poses,links_per_s_median,rays_per_link\n";
  std::map<std::string, io::Series> by_tags;

  for (const bench::BenchScene& bs : scenes) {
#ifdef __GLIBC__
    // The previous scene's freed pages go back to the system first: reused, they would make this scene read
    // smaller than it is (w1m 98 instead of 117 B/triangle after the smaller scenes, one process per scene).
    malloc_trim(0);
#endif
    const size_t rss0 = resident_bytes();
    std::vector<TriangleMesh> meshes = bench::scene_meshes(bs);
    const auto t0 = std::chrono::steady_clock::now();
    const auto scene = std::make_shared<const Scene>(std::move(meshes), MaterialAssignment{});
    const double build_s = seconds_since(t0);
    const size_t rss1 = resident_bytes();
    const double n_tri = double(scene->triangle_count());
    const bench::Workload w = bench::scene_workload(bs, tags, poses);
    const size_t planes = RaytracedChannel(scene).finder().plane_count();
    std::printf("%s: %zu triangles, %zu facets, %zu planes; scene + BVH build %.3f s; Embree %.0f B/triangle, "
                "resident %.0f B/triangle; %zu tags x %zu poses\n",
                bs.name.c_str(), scene->triangle_count(), scene->facets().size(), planes, build_s,
                scene->bvh().embree_bytes() / n_tri, double(rss1 - std::min(rss0, rss1)) / n_tri, w.tags.size(),
                w.antennas.size());
    for (const Setting& st : chosen) {
      const auto tc = std::chrono::steady_clock::now();
      const RaytracedChannel ch(scene, st.options);
      const double channel_s = seconds_since(tc);
      const CoveredRects* cov = ch.finder().covered_rects();
      const double cov_bytes = cov ? double(cov->bytes()) / n_tri : 0.0;
      const double cov_s = ch.finder().covered_build_s();
      if (cov)
        std::printf("  %-24s channel build %.3f s, of which covered rectangles %.3f s: %zu rectangles, %.1f B/triangle\n",
                    st.name.c_str(), channel_s, cov_s, cov->rect_count(), cov_bytes);
      else
        std::printf("  %-24s channel build %.3f s (search grids)\n", st.name.c_str(), channel_s);
      for (int threads : thread_counts) {
        omp_set_num_threads(threads);
        const Rate r = measure(ch, w, runs);
        std::printf("  %-24s %d thread%s  %12.0f links/s median (min %.0f, max %.0f)  %6.2f rays/link  %6.2f culled/link"
                    "  %6.2f mirror points/link  %5.2f reflections/link%s\n",
                    st.name.c_str(), threads, threads == 1 ? " " : "s", r.median, r.min, r.max, r.rays_per_link,
                    r.culled_per_link, r.mirror_points_per_link, r.reflections_per_link, packet_note(ch).c_str());
        csv << bs.name << "," << scene->triangle_count() << "," << scene->facets().size() << "," << planes << ","
            << build_s << "," << scene->bvh().embree_bytes() / n_tri << ","
            << double(rss1 - std::min(rss0, rss1)) / n_tri << "," << st.name << "," << threads << ","
            << w.tags.size() << "," << w.antennas.size() << "," << r.median << "," << r.min << "," << r.max << ","
            << r.rays_per_link << "," << r.culled_per_link << "," << cov_bytes << "," << cov_s << ","
            << r.mirror_points_per_link << "," << r.reflections_per_link << "\n";
        if (threads == 2) {
          auto& s = by_triangles[st.name];
          s.title = st.name, s.style = "linespoints";
          s.x.push_back(n_tri), s.y.push_back(r.median);
        }
      }
    }
    if (bs.name == "w1m" && !no_tags_sweep) {
      // Cost vs tags: linear in tags, the per-pose candidate search amortised over more of them.
      omp_set_num_threads(2);
      std::vector<int> counts{100, 1000, 10000, 100000};
      if (quick) counts = {100, 1000, 10000};
      for (const Setting& st : chosen) {
        const RaytracedChannel ch(scene, st.options);
        for (int n : counts) {
          // At least as many links per timed run as the levels above (tags × poses): at 100 tags × 4 poses a
          // run lasted ~0.1 ms and its figure was mostly the scheduler's (two full runs gave 3.4 M and 0.8 M
          // links/s). More poses measure the same thing, the per-pose cost included, over a longer time.
          const int poses_n = std::max(poses, (tags * poses + n - 1) / n);
          const bench::Workload wt = bench::scene_workload(bs, n, poses_n);
          const Rate r = measure(ch, wt, runs);
          std::printf("  %-24s 2 threads %7d tags %12.0f links/s  %6.2f rays/link%s\n", st.name.c_str(), n, r.median,
                      r.rays_per_link, packet_note(ch).c_str());
          tags_csv << bs.name << "," << st.name << ",2," << n << "," << poses_n << "," << r.median << ","
                   << r.rays_per_link << "\n";
          auto& s = by_tags[st.name];
          s.title = st.name, s.style = "linespoints";
          s.x.push_back(n), s.y.push_back(r.median);
        }
      }
    }
  }

  auto values = [](const std::map<std::string, io::Series>& m) {
    std::vector<io::Series> v;
    for (const Setting& st : settings())
      if (m.count(st.name)) v.push_back(m.at(st.name));
    return v;
  };
  // The charts plot the 2-thread figures; a run without them (--threads 1) has nothing to chart, and the
  // summary line lists only the files that were written.
  std::string written = "links_per_level.csv, links_vs_tags.csv";
  try {
    const auto has_points = [](const std::map<std::string, io::Series>& m) {
      for (const auto& [name, series] : m)
        if (!series.y.empty()) return true;
      return false;
    };
    if (has_points(by_triangles)) {
      io::Panel tri{"Links/s vs scene size (2 threads; tags on every row, antenna poses along the middle aisle)",
                     "triangles", "links / s", values(by_triangles), true, true};
      io::write_png(std::filesystem::path(out_dir) / "links_vs_triangles.png", {tri});
      written += ", links_vs_triangles.png";
    }
    if (has_points(by_tags)) {
      io::Panel tg{"Links/s vs tags per antenna pose (1 M-triangle warehouse, 2 threads)", "tags", "links / s",
                    values(by_tags), true, true};
      io::write_png(std::filesystem::path(out_dir) / "links_vs_tags.png", {tg});
      written += ", links_vs_tags.png";
    }
  } catch (const std::exception& e) {
    std::cerr << "bench_sweep: charts not written: " << e.what() << "\n";
  }
  std::printf("wrote %s in %s\n", written.c_str(), out_dir.c_str());
  return 0;
}
