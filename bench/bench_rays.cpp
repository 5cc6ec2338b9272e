// Ray throughput (Google Benchmark): our path finder's rays against a raw Embree loop on the same segments,
// the same scene, in the same process and at the same thread count.
//
//   occluded1_raw    rtcOccluded1 over every antenna–tag segment of the workload (the LoS visibility test)
//   occluded1_ours   PathFinder::trace at level `los` on the same links: exactly one rtcOccluded1 per link,
//                    plus everything the tracer does around it (checks, pattern gains, polarization, the path)
//   occluded16_raw   the same segments as rtcOccluded16 packets (16 tags of one antenna pose per packet)
//   los_ours         what RaytracedChannel::one_way does per thread at level los: PathFinder::trace_sum over
//                    each pose's tags, the visibility rays in packets of the width the channel measures on
//                    the first pose (printed; 1 = single rays)
// Tags are in Morton order (as RaytracedChannel::one_way traces them), so a packet's rays are coherent.
//   intersect1_raw   rtcIntersect1 on the candidate-search directions (spherical Fibonacci) of every pose
//   intersect1_ours  PathFinder::prepare_pose with the same number of candidate rays
// items_per_second = rays per second (real time, all threads). The `rfidray bench` driver turns the JSON
// output into ratios (ours / raw) per scene and thread count.
//
//   bench_rays [--scenes paper,w10k,...] [--tags N] [--poses N] [--candidate-rays N] [Google Benchmark flags]
//   bench_rays --compare-widths 1 [--scenes ...] [--tags N] [--poses N]
//     no timing: every link of the workload at level los through PathFinder::trace_sum at packet widths 4, 8
//     and 16 against single rays; prints how many links' h differ (packets and single rays may differ on
//     near-degenerate rays, raytrace/embree_scene.h).
#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>
#include <omp.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "bench/workload.h"
#include "raytrace/morton.h"
#include "raytrace/path_finder.h"
#include "raytrace/raytraced_channel.h"
#include "raytrace/scene.h"

using namespace rfidray;

namespace {

struct Segment {
  float org[3], dir[3], tnear, tfar;
};

struct Prepared {
  std::shared_ptr<const Scene> scene;
  bench::Workload work;
  std::vector<Segment> segments;  // pose-major: tags of pose 0, then pose 1, ...
  std::vector<Vec3> directions;   // candidate-search directions
  std::unique_ptr<PathFinder> los_finder, candidate_finder;
  std::vector<uint32_t> identity;  // 0 … tags − 1 (the tags are already in Morton order)
  int los_width = 1;               // measured as one_way does
};

struct Config {
  std::vector<std::string> scenes{"paper", "w10k", "w100k", "w1m", "w5m"};
  int tags = 2000, poses = 20, candidate_rays = 4096;
  bool compare_widths = false;
};

// --compare-widths: links whose h differs between packets and single rays.
void compare_widths(const std::string& name, Prepared& p) {
  const size_t n = p.work.tags.size();
  std::vector<std::complex<double>> single(n), packed(n);
  PoseCandidates c;
  size_t links = 0, visible = 0, differ[17] = {};
  for (const Endpoint& a : p.work.antennas) {
    p.los_finder->trace_sum(a, p.work.tags, p.identity, 865.7e6, c, 1, single);
    for (const auto& x : single) visible += x != 0.0;
    links += n;
    for (int w : {4, 8, 16}) {
      p.los_finder->trace_sum(a, p.work.tags, p.identity, 865.7e6, c, w, packed);
      for (size_t k = 0; k < n; ++k) differ[w] += packed[k] != single[k];
    }
  }
  std::printf("%s: %zu links, %zu visible; links whose h differs from single rays: width 4: %zu, 8: %zu, 16: %zu\n",
              name.c_str(), links, visible, differ[4], differ[8], differ[16]);
}

std::map<std::string, std::unique_ptr<Prepared>> g_prepared;

Prepared& prepare(const std::string& name, const Config& c) {
  auto& slot = g_prepared[name];
  if (slot) return *slot;
  slot = std::make_unique<Prepared>();
  Prepared& p = *slot;
  const bench::BenchScene bs = bench::find_bench_scene(name);
  p.scene = std::make_shared<const Scene>(bench::scene_meshes(bs), MaterialAssignment{});
  p.work = bench::scene_workload(bs, c.tags, c.poses);
  // Tags in Morton order, as RaytracedChannel::one_way traces them.
  std::stable_sort(p.work.tags.begin(), p.work.tags.end(), [](const Endpoint& x, const Endpoint& y) {
    return morton_key(x.pose.position) < morton_key(y.pose.position);
  });
  const double eps = TraceOptions{}.endpoint_epsilon_m;
  for (const Endpoint& a : p.work.antennas)
    for (const Endpoint& t : p.work.tags) {
      const Vec3 d = t.pose.position - a.pose.position;
      const double len = d.norm();
      const Vec3 u = d / len;
      const double e = std::min(eps, 0.25 * len);  // as PathFinder::direct_path
      p.segments.push_back({{float(a.pose.position.x()), float(a.pose.position.y()), float(a.pose.position.z())},
                            {float(u.x()), float(u.y()), float(u.z())},
                            float(e),
                            float(len - e)});
    }
  TraceOptions los;
  los.level = ChannelLevel::kLos;
  p.los_finder = std::make_unique<PathFinder>(p.scene, los);
  for (uint32_t i = 0; i < p.work.tags.size(); ++i) p.identity.push_back(i);
  p.los_width = fastest_los_packet_width(*p.los_finder, p.work.antennas.front(), p.work.tags, p.identity);
  std::fprintf(stderr, "bench_rays: %s: level-los packet width measured on the first pose: %d\n", name.c_str(),
               p.los_width);
  TraceOptions cand;
  cand.candidate_rays = c.candidate_rays;
  p.candidate_finder = std::make_unique<PathFinder>(p.scene, cand);
  const double golden = kPi * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < c.candidate_rays; ++i) {
    const double z = 1.0 - (2.0 * i + 1.0) / c.candidate_rays;
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    p.directions.emplace_back(r * std::cos(golden * i), r * std::sin(golden * i), z);
  }
  return p;
}

// This thread's share [begin, end) of n items.
std::pair<size_t, size_t> slice(const benchmark::State& state, size_t n) {
  const size_t t = static_cast<size_t>(state.thread_index()), k = static_cast<size_t>(state.threads());
  return {n * t / k, n * (t + 1) / k};
}

void occluded1_raw(benchmark::State& state, Prepared* p) {
  const RTCScene scene = p->scene->bvh().handle();
  const auto [b, e] = slice(state, p->segments.size());
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  size_t blocked = 0;
  for (auto _ : state) {
    for (size_t i = b; i < e; ++i) {
      const Segment& s = p->segments[i];
      RTCRay ray;
      ray.org_x = s.org[0], ray.org_y = s.org[1], ray.org_z = s.org[2];
      ray.dir_x = s.dir[0], ray.dir_y = s.dir[1], ray.dir_z = s.dir[2];
      ray.tnear = s.tnear, ray.tfar = s.tfar;
      ray.time = 0.0f, ray.mask = 0xFFFFFFFFu, ray.id = 0, ray.flags = 0;
      rtcOccluded1(scene, &context, &ray);
      blocked += ray.tfar < 0.0f;
    }
  }
  benchmark::DoNotOptimize(blocked);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * (e - b)));
  state.counters["blocked_fraction"] = benchmark::Counter(
      double(blocked) / double(std::max<size_t>(1, state.iterations() * (e - b))), benchmark::Counter::kAvgThreads);
}

void occluded16_raw(benchmark::State& state, Prepared* p) {
  const RTCScene scene = p->scene->bvh().handle();
  const auto [b, e] = slice(state, p->segments.size());
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;  // rays of a packet share their origin
  size_t blocked = 0;
  alignas(64) RTCRay16 ray;
  alignas(64) int valid[16];
  for (auto _ : state) {
    for (size_t i = b; i < e; i += 16) {
      const size_t n = std::min<size_t>(16, e - i);
      for (size_t k = 0; k < 16; ++k) {
        valid[k] = k < n ? -1 : 0;
        const Segment& s = p->segments[i + std::min(k, n - 1)];
        ray.org_x[k] = s.org[0], ray.org_y[k] = s.org[1], ray.org_z[k] = s.org[2];
        ray.dir_x[k] = s.dir[0], ray.dir_y[k] = s.dir[1], ray.dir_z[k] = s.dir[2];
        ray.tnear[k] = s.tnear, ray.tfar[k] = s.tfar;
        ray.time[k] = 0.0f, ray.mask[k] = 0xFFFFFFFFu, ray.id[k] = 0, ray.flags[k] = 0;
      }
      rtcOccluded16(valid, scene, &context, &ray);
      for (size_t k = 0; k < n; ++k) blocked += ray.tfar[k] < 0.0f;
    }
  }
  benchmark::DoNotOptimize(blocked);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * (e - b)));
  state.counters["blocked_fraction"] = benchmark::Counter(
      double(blocked) / double(std::max<size_t>(1, state.iterations() * (e - b))), benchmark::Counter::kAvgThreads);
}

void occluded1_ours(benchmark::State& state, Prepared* p) {
  const size_t n_tags = p->work.tags.size();
  const auto [b, e] = slice(state, p->segments.size());
  PoseCandidates candidates;
  std::vector<TracedPath> out;
  size_t blocked = 0;
  for (auto _ : state) {
    for (size_t i = b; i < e; ++i) {
      p->los_finder->trace(p->work.antennas[i / n_tags], p->work.tags[i % n_tags], 865.7e6, candidates, out);
      blocked += out.empty();
    }
  }
  benchmark::DoNotOptimize(blocked);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * (e - b)));
  state.counters["blocked_fraction"] = benchmark::Counter(
      double(blocked) / double(std::max<size_t>(1, state.iterations() * (e - b))), benchmark::Counter::kAvgThreads);
}

void los_ours(benchmark::State& state, Prepared* p) {
  const size_t n_tags = p->work.tags.size();
  const auto [b, e] = slice(state, p->segments.size());
  PoseCandidates candidates;
  std::vector<std::complex<double>> h(n_tags);
  size_t blocked = 0;
  for (auto _ : state) {
    for (size_t i = b; i < e;) {
      const size_t pose = i / n_tags, first = i % n_tags, count = std::min(e - i, n_tags - first);
      p->los_finder->trace_sum(p->work.antennas[pose], p->work.tags,
                               std::span<const uint32_t>(p->identity).subspan(first, count), 865.7e6, candidates,
                               p->los_width, h);
      for (size_t k = first; k < first + count; ++k) blocked += h[k] == 0.0;
      i += count;
    }
  }
  // (h is read above, so nothing is optimised away; no DoNotOptimize(blocked): with this GCC and Google
  // Benchmark's "+m,r" constraint it handed back another register's value here.)
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * (e - b)));
  state.counters["blocked_fraction"] = benchmark::Counter(
      double(blocked) / double(std::max<size_t>(1, state.iterations() * (e - b))), benchmark::Counter::kAvgThreads);
  state.counters["packet_width"] = benchmark::Counter(double(p->los_width), benchmark::Counter::kAvgThreads);
}

void intersect1_raw(benchmark::State& state, Prepared* p) {
  const RTCScene scene = p->scene->bvh().handle();
  const size_t n_dir = p->directions.size();
  const auto [b, e] = slice(state, p->work.antennas.size() * n_dir);
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  size_t hits = 0;
  const float eps = float(TraceOptions{}.endpoint_epsilon_m);
  for (auto _ : state) {
    for (size_t i = b; i < e; ++i) {
      const Vec3& o = p->work.antennas[i / n_dir].pose.position;
      const Vec3& d = p->directions[i % n_dir];
      RTCRayHit rh;
      rh.ray.org_x = float(o.x()), rh.ray.org_y = float(o.y()), rh.ray.org_z = float(o.z());
      rh.ray.dir_x = float(d.x()), rh.ray.dir_y = float(d.y()), rh.ray.dir_z = float(d.z());
      rh.ray.tnear = eps, rh.ray.tfar = 1e30f;
      rh.ray.time = 0.0f, rh.ray.mask = 0xFFFFFFFFu, rh.ray.id = 0, rh.ray.flags = 0;
      rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
      rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
      rtcIntersect1(scene, &context, &rh);
      hits += rh.hit.geomID != RTC_INVALID_GEOMETRY_ID;
    }
  }
  benchmark::DoNotOptimize(hits);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * (e - b)));
}

void intersect1_ours(benchmark::State& state, Prepared* p) {
  omp_set_num_threads(1);  // prepare_pose would fork its own team: keep the benchmark's thread count
  const size_t n_dir = p->directions.size();
  const auto [b, e] = slice(state, p->work.antennas.size());  // whole poses per thread
  PoseCandidates c;
  size_t planes = 0;
  for (auto _ : state) {
    for (size_t i = b; i < e; ++i) {
      p->candidate_finder->prepare_pose(p->work.antennas[i].pose.position, c);
      planes += c.planes.size();
    }
  }
  benchmark::DoNotOptimize(planes);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * (e - b) * n_dir));
  state.counters["planes_per_pose"] = benchmark::Counter(double(planes) / double(std::max<size_t>(1, state.iterations() * (e - b))), benchmark::Counter::kAvgThreads);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);  // removes its own --benchmark_* flags
  Config c;
  for (int i = 1; i < argc; ++i) {
    const std::string k = argv[i];
    if (i + 1 >= argc) {
      std::fprintf(stderr, "bench_rays: option %s needs a value\n", k.c_str());
      return 2;
    }
    const std::string v = argv[++i];
    if (k == "--scenes") c.scenes = bench::split_commas(v);
    else if (k == "--tags") c.tags = std::atoi(v.c_str());
    else if (k == "--poses") c.poses = std::atoi(v.c_str());
    else if (k == "--candidate-rays") c.candidate_rays = std::atoi(v.c_str());
    else if (k == "--compare-widths") c.compare_widths = std::atoi(v.c_str()) != 0;
    else {
      std::fprintf(stderr, "bench_rays: unknown option %s\n", k.c_str());
      return 2;
    }
  }
  if (c.tags < 1 || c.poses < 1 || c.candidate_rays < 1) {
    std::fprintf(stderr, "bench_rays: --tags, --poses and --candidate-rays must be >= 1\n");
    return 2;
  }
  try {
    for (const std::string& name : c.scenes) {
      Prepared* p = &prepare(name, c);
      if (c.compare_widths) {
        compare_widths(name, *p);
        continue;
      }
      std::fprintf(stderr, "bench_rays: %s: %zu triangles, %zu segments\n", name.c_str(), p->scene->triangle_count(),
                   p->segments.size());
      // Interleaved raw/ours so both see the same machine state; one thread count after the other.
      for (int threads : {1, 2}) {
        auto reg = [&](const char* what, void (*fn)(benchmark::State&, Prepared*)) {
          benchmark::RegisterBenchmark((std::string(what) + "/" + name).c_str(),
                                       [fn](benchmark::State& st, Prepared* pp) {
                                         fn(st, pp);
                                         st.counters["triangles"] = benchmark::Counter(
                                             double(pp->scene->triangle_count()), benchmark::Counter::kAvgThreads);
                                       },
                                       p)
              ->Threads(threads)
              ->UseRealTime()
              ->Unit(benchmark::kMillisecond);
        };
        reg("occluded1_raw", occluded1_raw);
        reg("occluded1_ours", occluded1_ours);
        reg("occluded16_raw", occluded16_raw);
        reg("los_ours", los_ours);
        reg("intersect1_raw", intersect1_raw);
        reg("intersect1_ours", intersect1_ours);
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_rays: %s\n", e.what());
    return 2;
  }
  if (c.compare_widths) return 0;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
