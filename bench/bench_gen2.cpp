// EPC Gen2 inventory (core/gen2_simulation.h) on the ideal channel: how fast the simulation runs, and what a
// reader reads as the tag population grows.
//
//   bench_gen2 [--out DIR] [--runs N]
//
// 1. speed: 1000 static tags within 1-4 m of one fixed antenna (physical model, every tag powered), a
//    max-throughput reader, session 0, dual target, Q algorithm from Q = 4; 60 s simulated on one thread;
//    wall time of simulate() over --runs runs (median, min, max).
// 2. throughput: for each preset and N = 1 … 1000 tags, 10 s simulated, the same inventory: reads/s (all tags),
//    reads per tag per second, and the share of empty / single / collided slots -> DIR/throughput.csv.
// 3. one tag, fixed Q = 0, dual target: reads/s against 1 / (Query + T1 + RN16 + T2 + ACK + T1 + EPC + T2).
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <vector>

#include "core/channel.h"
#include "core/gen2_reader.h"
#include "core/simulation.h"

using namespace rfidray;

namespace {

Scenario population(size_t n_tags, const std::string& preset, double duration_s, Gen2QMode mode, int q) {
  Scenario s;
  AntennaSpec a;
  a.reader.name = "reader";
  a.reader.model = ReaderModelKind::kPhysical;
  a.motion.pose.position = Vec3(0, 0, 1);
  Gen2ReaderSpec g;
  g.link = *gen2_preset(preset);
  g.preset = preset;
  g.session = 0;
  g.target = Gen2Target::kAB;
  g.q = q;
  g.q_mode = mode;
  a.gen2 = g;
  s.antennas.push_back(a);
  // Tags on a sphere shell 1 m to 4 m from the antenna (golden-angle spiral), all within the −20 dBm chip's reach.
  for (size_t i = 0; i < n_tags; ++i) {
    TagSpec t;
    t.tag.name = "t" + std::to_string(i);
    const double r = 1.0 + 3.0 * (i + 0.5) / n_tags;
    const double z = 1.0 - 2.0 * (i + 0.5) / n_tags, phi = 2.399963229728653 * i;
    const double rho = std::sqrt(std::max(0.0, 1.0 - z * z));
    t.motion.pose.position = Vec3(r * rho * std::cos(phi), r * rho * std::sin(phi), 1.0 + r * z);
    s.tags.push_back(t);
  }
  s.duration_s = duration_s;
  return s;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Gen2 inventory: simulation speed and read throughput against tag population"};
  std::string out = "bench/results/gen2";
  int runs = 5;
  app.add_option("--out", out, "Output directory");
  app.add_option("--runs", runs, "Timed runs of the speed case")->check(CLI::Range(1, 100));
  CLI11_PARSE(app, argc, argv);
  std::filesystem::create_directories(out);
  const IdealChannel channel;
  SimulationOptions one_thread;
  one_thread.threads = 1;

  // 1. Speed.
  {
    const Scenario s = population(1000, "max_throughput", 60.0, Gen2QMode::kAdaptive, 4);
    std::vector<double> wall;
    size_t reads = 0;
    for (int r = 0; r < runs; ++r) {
      const auto t0 = std::chrono::steady_clock::now();
      const SimulationResult res = simulate(s, channel, one_thread);
      wall.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      reads = res.antennas[0].reads.size();
    }
    std::printf("speed: 1000 tags, 60 s simulated, max_throughput, 1 thread: median %.3f s (min %.3f, max %.3f) "
                "over %d runs; %zu reads\n",
                median(wall), *std::min_element(wall.begin(), wall.end()), *std::max_element(wall.begin(), wall.end()),
                runs, reads);
  }

  // 2. Throughput against population.
  {
    std::ofstream csv(std::filesystem::path(out) / "throughput.csv");
    csv << "preset,tags,reads_per_s,reads_per_tag_per_s,min_tag_reads_per_s,empty_share,single_share,collided_share,"
           "tags_never_read\n";
    const double duration_s = 10.0;
    for (const std::string& preset : gen2_preset_names())
      for (size_t n : {1, 2, 5, 10, 20, 50, 100, 200, 500, 1000}) {
        const Scenario s = population(n, preset, duration_s, Gen2QMode::kAdaptive, 4);
        const SimulationResult res = simulate(s, channel, one_thread);
        const AntennaResult& a = res.antennas[0];
        std::vector<uint64_t> per_tag(n, 0);
        for (const ReadRecord& r : a.reads) ++per_tag[r.tag];
        const uint64_t lo = *std::min_element(per_tag.begin(), per_tag.end());
        const size_t never = static_cast<size_t>(std::count(per_tag.begin(), per_tag.end(), 0u));
        const double slots = static_cast<double>(a.gen2->slots());
        char line[512];
        std::snprintf(line, sizeof line, "%s,%zu,%.2f,%.4f,%.4f,%.4f,%.4f,%.4f,%zu\n", preset.c_str(), n,
                      a.reads.size() / duration_s, a.reads.size() / duration_s / n, lo / duration_s,
                      a.gen2->empty / slots, a.gen2->single / slots, a.gen2->collided / slots, never);
        csv << line;
        std::printf("throughput: %s", line);
      }
  }

  // 3. One tag, fixed Q = 0, dual target: one read per Query→RN16→ACK→EPC cycle.
  for (const std::string& preset : gen2_preset_names()) {
    const Scenario s = population(1, preset, 10.0, Gen2QMode::kFixed, 0);
    const SimulationResult res = simulate(s, channel, one_thread);
    const Gen2LinkTiming t = gen2_link_timing(*gen2_preset(preset), "gen2");
    std::printf("one tag, %s, Q = 0 fixed: %.1f reads/s simulated; formula 1/cycle = 1/%.3f µs = %.1f reads/s\n",
                preset.c_str(), res.antennas[0].reads.size() / 10.0, t.single_slot_s(t.query_s) * 1e6,
                1.0 / t.single_slot_s(t.query_s));
  }
  return 0;
}
