// Stability sweeps of the three localization methods on synthetic histories (paper eq. 4 phase model,
// ideal channel: φ = φ0 + 4πD/λ + n mod 2π, 12-bit quantization), one parameter at a time around a base case:
// L-shaped path at 1.68 m (6 m along +Y then 3 m along +X, so no mirror ambiguity), 15 Hz, 0.35 m/s,
// σφ = 0.1 rad, tag 2 m from the first leg at 2.05 m, tag height known. The multipath sweep adds a metal wall
// behind the tag: every read's phase moves by the ray-traced round trip's difference from free space (the LoS
// path plus the wall's specular reflection), then is quantized again.
//   localize_sweeps [--trials N] [--out DIR] [--only noise|spacing|aperture|distance|multipath]
// Writes DIR/localize_sweep_<name>.csv and .png: median error and failure rate per method vs the parameter.
#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>

#include "bench/localize_common.h"
#include "core/reader_model.h"
#include "raytrace/raytraced_channel.h"
#include "raytrace/warehouse.h"
#include "io/plot.h"
#include "localization/summary.h"
#include "localization/synthetic.h"
#include "core/units.h"

using namespace rfidray;

namespace {

struct Case {
  double wall_m = 0.0;  // > 0: a metal wall parallel to the first leg, this far behind the tag (multipath)
  double noise_rad = 0.1;
  double spacing_fraction = 0.35 / 15.0 / wavelength_m(865.7e6);  // antenna move per read / λ
  double path_length_m = 9.0;
  double distance_m = 2.0;
};

struct Sweep {
  std::string name, label;
  std::vector<double> values;
  bool log_x = false;
  void (*apply)(Case&, double);
};

const double kLambda = wavelength_m(865.7e6);

// Multipath of a metal wall (x = tag.x + wall, 4 m high, as long as the path plus 10 m) on every read: the
// phase moves by arg of the ray-traced round trip against the free-space one, −arg(h²) − 4πD/λ.
void add_wall_multipath(std::vector<loc::TagReads>& trials, const Vec3& tag, double wall_m, double path_m) {
  TriangleMesh wall;
  wall.name = "wall";
  wall.material_names = {"metal"};
  add_quad(wall, Vec3(tag.x() + wall_m, tag.y() - path_m - 5.0, 0.0), Vec3(0, 0, 4.0), Vec3(0, 2 * path_m + 10.0, 0), 0);
  const auto scene = std::make_shared<const Scene>(std::vector<TriangleMesh>{wall}, MaterialAssignment{});
  const RaytracedChannel traced(scene);
  const IdealChannel ideal;
  Endpoint t;
  t.pose.position = tag;
  for (loc::TagReads& r : trials)
    for (loc::ReadGroup& g : r.groups)
      for (loc::PhaseRead& p : g.reads) {
        Endpoint a;
        a.pose.position = p.antenna_m;
        std::complex<double> hm, hi;
        traced.one_way(a, std::span(&t, 1), g.frequency_hz, std::span(&hm, 1));
        ideal.one_way(a, std::span(&t, 1), g.frequency_hz, std::span(&hi, 1));
        p.phase_rad = quantize_phase(std::fmod(p.phase_rad - std::arg(hm * hm) + std::arg(hi * hi) + 4 * kPi, 2 * kPi), 12);
      }
}

std::vector<loc::TagReads> make_trials(const Case& c, int trials, Vec3& tag) {
  // First leg 2/3 of the path along +Y centred on the tag's y, second leg 1/3 along +X.
  const double leg1 = c.path_length_m * 2.0 / 3.0, leg2 = c.path_length_m / 3.0;
  const double y0 = 0.5 - leg1 / 2.0;
  tag = Vec3(c.distance_m, 0.5, 2.05);
  const double speed = c.spacing_fraction * kLambda * 15.0;
  const auto path = loc::sample_polyline({Vec3(0, y0, 1.68), Vec3(0, y0 + leg1, 1.68), Vec3(leg2, y0 + leg1, 1.68)},
                                         speed, 15.0, -kPi / 2);
  std::vector<loc::TagReads> out;
  for (int t = 0; t < trials; ++t) {
    loc::SyntheticSpec s;
    s.phase_offsets_rad = {0.7 + t};
    s.phase_noise_rad = c.noise_rad;
    s.phase_bits = 12;
    s.seed = 2022;
    s.stream = static_cast<uint64_t>(t);
    out.push_back(loc::synthesize("trial" + std::to_string(t), tag, path, s));
  }
  if (c.wall_m > 0.0) add_wall_multipath(out, tag, c.wall_m, c.path_length_m);
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Localization stability sweeps (synthetic; ideal channel, and a metal wall for multipath)"};
  int trials = 5;
  std::string out_dir = "localize_sweeps_out", only;
  app.add_option("--trials", trials, "noise realisations per point")->capture_default_str();
  app.add_option("--out", out_dir, "output directory")->capture_default_str();
  app.add_option("--only", only, "run one sweep: noise | spacing | aperture | distance | multipath");
  CLI11_PARSE(app, argc, argv);
  std::filesystem::create_directories(out_dir);

  const std::vector<Sweep> sweeps{
      {"noise", "phase noise sigma (rad)", {0.01, 0.02, 0.05, 0.1, 0.2, 0.3, 0.5, 0.7, 1.0}, true,
       [](Case& c, double v) { c.noise_rad = v; }},
      {"spacing", "antenna move per read (wavelengths; unwrapping limit 0.25)", {0.05, 0.1, 0.15, 0.2, 0.24, 0.27, 0.3, 0.4, 0.5}, false,
       [](Case& c, double v) { c.spacing_fraction = v; }},
      {"aperture", "path length (m)", {0.3, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 5.0, 9.0}, true,
       [](Case& c, double v) { c.path_length_m = v; }},
      {"distance", "tag distance from the path (m)", {0.5, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0}, false,
       [](Case& c, double v) { c.distance_m = v; }},
      {"multipath", "metal wall behind the tag, distance (m)", {0.05, 0.1, 0.2, 0.35, 0.5, 1.0, 2.0, 4.0, 8.0}, true,
       [](Case& c, double v) { c.wall_m = v; }},
  };
  const std::vector<loc::Method> methods{loc::Method::kHyperbolic, loc::Method::kNlls, loc::Method::kSar};

  for (const Sweep& sw : sweeps) {
    if (!only.empty() && only != sw.name) continue;
    const auto base = std::filesystem::path(out_dir) / ("localize_sweep_" + sw.name);
    std::ofstream csv(base.string() + ".csv");
    csv << sw.name << ",method,trials,ok,failure_rate,median_error_m,mean_error_m,max_error_m,mean_time_ms,reasons\n"
        << std::setprecision(6);
    std::vector<io::Series> err_series, fail_series;
    std::cout << "\n== sweep " << sw.name << " (" << sw.label << "), " << trials << " trials per point: median error mm / failures\n";
    std::cout << std::setw(8) << sw.name;
    for (loc::Method m : methods) std::cout << std::setw(22) << loc::to_string(m);
    std::cout << "\n";
    std::vector<std::vector<std::string>> rows(sw.values.size());
    for (loc::Method m : methods) {
      io::Series es{loc::to_string(m), {}, {}, "linespoints"}, fs{loc::to_string(m), {}, {}, "linespoints"};
      for (size_t vi = 0; vi < sw.values.size(); ++vi) {
        const double v = sw.values[vi];
        Case c;
        sw.apply(c, v);
        Vec3 tag;
        const auto reads = make_trials(c, trials, tag);
        loc::LocalizeOptions o;
        o.height_known = true;
        o.tag_height_m = tag.z();
        o.max_range_m = std::max(4.0, c.distance_m + 2.5);
        std::vector<double> errors, times;
        int failed = 0;
        std::map<std::string, int> reasons;
        for (const auto& r : reads) {
          const bench::TimedResult t = bench::timed_localize(m, r, o);
          times.push_back(t.time_ms);
          if (t.result.ok) errors.push_back((t.result.position - tag).norm());
          else ++failed, ++reasons[loc::to_string(t.result.reason)];
        }
        const loc::ErrorSummary s = loc::summarize(errors, failed, times);
        const double fail_rate = static_cast<double>(failed) / trials;
        std::string why;
        for (const auto& [k, n] : reasons) why += k + " x" + std::to_string(n) + "; ";
        csv << v << "," << loc::to_string(m) << "," << trials << "," << s.ok << "," << fail_rate << ","
            << s.median_error_m << "," << s.mean_error_m << "," << s.max_error_m << "," << s.mean_time_ms << ","
            << why << "\n";
        if (s.ok > 0) es.x.push_back(v), es.y.push_back(1000.0 * s.median_error_m);
        fs.x.push_back(v), fs.y.push_back(fail_rate);
        std::ostringstream cell;
        cell << std::fixed << std::setprecision(1);
        if (s.ok > 0) cell << 1000.0 * s.median_error_m;
        else cell << "-";
        cell << " / " << failed;
        rows[vi].push_back(cell.str());
      }
      err_series.push_back(es);
      fail_series.push_back(fs);
    }
    for (size_t vi = 0; vi < sw.values.size(); ++vi) {
      std::cout << std::setw(8) << sw.values[vi];
      for (const auto& cell : rows[vi]) std::cout << std::setw(22) << cell;
      std::cout << "\n";
    }
    try {
      io::write_png(base.string() + ".png",
                     {io::Panel{"Median error of ok results vs " + sw.label, sw.label, "median error (mm)", err_series, sw.log_x, true},
                      io::Panel{"Failure rate (status failed) vs " + sw.label, sw.label, "failed fraction", fail_series, sw.log_x, false}});
    } catch (const std::exception& e) {
      std::cerr << "chart not written: " << e.what() << "\n";
    }
  }
  return 0;
}
