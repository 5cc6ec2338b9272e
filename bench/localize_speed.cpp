// Milliseconds per tag per localization method at a given number of reads, one thread (issue goal: ≤ 10 ms at
// 1 000 reads). Reads: the public real-read set's geometry (1 m straight aperture, tag 0.88 m away, 8 carriers
// 920.625 … 924.125 MHz, 0.1 rad phase noise, 12-bit phase), continuous sampling. Median of --repeats runs.
// Output: localize_speed.csv (method, reads, median_ms, min_ms, status of the last run).
#include <omp.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "localization/methods.h"
#include "core/units.h"
#include "localization/synthetic.h"

using namespace rfidray;

int main(int argc, char** argv) {
  CLI::App app{"ms per tag per localization method, one thread"};
  std::string out_dir = ".";
  std::vector<int> reads{1000, 4000};
  int repeats = 5;
  std::vector<std::string> method_names{"hyperbolic", "nlls", "sar"};
  app.add_option("--out", out_dir, "output directory")->capture_default_str();
  app.add_option("--reads", reads, "reads per tag (several)")->capture_default_str();
  app.add_option("--repeats", repeats, "runs per point (median)")->capture_default_str()->check(CLI::PositiveNumber);
  app.add_option("--methods", method_names, "methods to time (several)")->capture_default_str();
  CLI11_PARSE(app, argc, argv);
  std::vector<loc::Method> methods;
  for (const std::string& name : method_names) {
    loc::Method m;
    if (!loc::parse_method(name, m)) {
      std::fprintf(stderr, "localize_speed: --methods: unknown method '%s'\n", name.c_str());
      return 2;
    }
    methods.push_back(m);
  }
  omp_set_num_threads(1);
  std::filesystem::create_directories(out_dir);
  std::ofstream csv(std::filesystem::path(out_dir) / "localize_speed.csv");
  csv << "method,reads,median_ms,min_ms,status\n";
  const Vec3 tag(0.5, 0.88, 0.0);
  for (int n : reads) {
    // n reads over 8 carriers along x in [0.02, 0.98] m, antenna facing +y.
    const double rate_hz = n / 48.0;
    const auto path = loc::sample_polyline({Vec3(0.02, 0, 0), Vec3(0.98, 0, 0)}, 0.02, rate_hz, kPi / 2);
    loc::SyntheticSpec spec;
    spec.frequencies_hz.clear();
    for (int k = 0; k < 8; ++k) spec.frequencies_hz.push_back(920.625e6 + 0.5e6 * k);
    spec.phase_offsets_rad = {0.0, 0.4, 1.1, 2.0, 2.9, 0.3, 1.7, 5.0};
    spec.hop_dwell_s = 1.0 / rate_hz;  // a carrier per read: every carrier is read every 8 reads (no gap > 1 s)
    spec.phase_noise_rad = 0.1;
    spec.phase_bits = 12;
    const loc::TagReads reads_of_tag = loc::synthesize("t", tag, path, spec);
    loc::LocalizeOptions o;
    o.height_known = true;
    o.tag_height_m = 0.0;
    o.max_range_m = 3.0;
    o.mirror_prior = loc::MirrorPrior::kBoresight;
    for (loc::Method m : methods) {
      std::vector<double> ms;
      loc::LocalizeResult last;
      for (int r = 0; r < repeats; ++r) {
        const auto t0 = std::chrono::steady_clock::now();
        last = loc::localize(m, reads_of_tag, o);
        ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count());
      }
      std::sort(ms.begin(), ms.end());
      const double median = ms[ms.size() / 2];
      csv << loc::to_string(m) << ',' << reads_of_tag.read_count() << ',' << median << ',' << ms.front() << ','
          << (last.ok ? "ok" : loc::to_string(last.reason)) << '\n';
      std::printf("%-10s %6zu reads: median %8.2f ms, min %8.2f ms (%d runs, 1 thread) %s\n", loc::to_string(m),
                  reads_of_tag.read_count(), median, ms.front(), repeats, last.ok ? "ok" : loc::to_string(last.reason));
    }
  }
  return 0;
}
