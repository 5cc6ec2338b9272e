// Links/s of the ray-traced channel (chrono sweep, median of runs): the paper warehouse and a parametric
// warehouse of ≥ 1 M triangles, levels los / los+blocked / single-bounce, a fixed thread count.
//   bench_links [--threads N] [--runs N] [--rows R --racks K --shelves S --tessellation T] [--tags N] [--poses N]
// Each run: for every antenna pose along the main aisle, one Channel::one_way call over all tags (the batch
// shares the candidate search of the pose, as `rfidray simulate` does).
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "raytrace/raytraced_channel.h"
#include "raytrace/warehouse.h"

using namespace rfidray;

namespace {

struct Args {
  int threads = 2, runs = 5, tags = 2000, poses = 20, candidate_rays = 0;
  WarehouseParams big{.rows = 20, .racks_per_row = 60, .shelves = 5, .tessellation = 3};
};

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Endpoint endpoint(const Vec3& p) {
  Endpoint e;
  e.pose.position = p;
  return e;  // isotropic, linear along z
}

struct Workload {
  std::vector<Endpoint> antennas, tags;
};

// Tags on rack fronts (5 cm in front, 5 cm above a shelf), antennas along an aisle at 1.0 m.
Workload paper_workload(int n_tags, int n_poses) {
  Workload w;
  const double ys[] = {0.57, -1.24, -3.03, -4.82, -6.75, -8.66, -7.70, -3.03, 1.44, 5.95};
  for (int i = 0; i < n_tags; ++i) {
    const bool east = i % 10 < 6;
    const double y = ys[i % 10] + 0.01 * (i / 10 % 50);
    w.tags.push_back(endpoint(east ? Vec3(2.90, y, 2.05) : Vec3(-4.85, y, 1.85)));
  }
  for (int k = 0; k < n_poses; ++k) w.antennas.push_back(endpoint(Vec3(-1.0, -10.0 + 18.0 * k / std::max(1, n_poses - 1), 1.0)));
  return w;
}

Workload big_workload(const WarehouseParams& p, int n_tags, int n_poses) {
  Workload w;
  const double pitch = p.rack_length_m + 0.1, row = p.rack_depth_m + p.aisle_m;
  const double length = p.racks_per_row * pitch;
  for (int i = 0; i < n_tags; ++i) {
    const int r = i % p.rows;
    const int s = (i / p.rows) % p.shelves;
    const double y = std::fmod(0.37 * i, length - 0.2) + 0.1;
    w.tags.push_back(endpoint(Vec3(r * row + p.aisle_m - 0.05, y, 0.15 + s * p.shelf_spacing_m + 0.05)));
  }
  // Poses along the middle aisle.
  const int mid = p.rows / 2;
  for (int k = 0; k < n_poses; ++k)
    w.antennas.push_back(endpoint(Vec3(mid * row + 0.5 * p.aisle_m, length * (k + 0.5) / n_poses, 1.0)));
  return w;
}

void run_scene(const char* name, std::vector<TriangleMesh> meshes, const Workload& w, const Args& a) {
  size_t triangles = 0;
  for (const auto& m : meshes) triangles += m.triangle_count();
  const auto t0 = std::chrono::steady_clock::now();
  const auto scene = std::make_shared<const Scene>(std::move(meshes), MaterialAssignment{});
  const double build_s = seconds_since(t0);
  std::printf("%s: %zu triangles, %zu facets, scene+BVH build %.3f s; %zu tags x %zu antenna poses, %d threads\n",
              name, triangles, scene->facets().size(), build_s, w.tags.size(), w.antennas.size(), a.threads);
  for (auto level : {ChannelLevel::kLos, ChannelLevel::kLosBlocked, ChannelLevel::kSingleBounce}) {
    TraceOptions o;
    o.level = level;
    o.candidate_rays = a.candidate_rays;
    const RaytracedChannel ch(scene, o);
    std::vector<std::complex<double>> h(w.tags.size());
    std::vector<double> rates;
    double checksum = 0.0;
    for (int r = 0; r < a.runs; ++r) {
      const auto t1 = std::chrono::steady_clock::now();
      for (const Endpoint& ant : w.antennas) {
        ch.one_way(ant, w.tags, 865.7e6, h);
        checksum += std::abs(h[0]);
      }
      rates.push_back(double(w.tags.size() * w.antennas.size()) / seconds_since(t1));
    }
    std::sort(rates.begin(), rates.end());
    std::printf("  %-14s median %12.0f links/s  (min %.0f, max %.0f over %d runs; checksum %.3e)\n", to_string(level),
                rates[rates.size() / 2], rates.front(), rates.back(), a.runs, checksum);
  }
  std::printf("  planes (fast-mode plane groups): %zu\n", RaytracedChannel(scene).finder().plane_count());
}

}  // namespace

int main(int argc, char** argv) {
  Args a;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const int v = std::atoi(argv[i + 1]);
    if (k == "--threads") a.threads = v;
    else if (k == "--runs") a.runs = v;
    else if (k == "--tags") a.tags = v;
    else if (k == "--poses") a.poses = v;
    else if (k == "--candidate-rays") a.candidate_rays = v;
    else if (k == "--rows") a.big.rows = v;
    else if (k == "--racks") a.big.racks_per_row = v;
    else if (k == "--shelves") a.big.shelves = v;
    else if (k == "--tessellation") a.big.tessellation = v;
    else {
      std::fprintf(stderr, "unknown option %s\n", k.c_str());
      return 2;
    }
  }
  omp_set_num_threads(a.threads);
  run_scene("paper warehouse", paper_warehouse_meshes(), paper_workload(a.tags, a.poses), a);
  run_scene("parametric warehouse", generate_warehouse(a.big), big_workload(a.big, a.tags, a.poses), a);
  return 0;
}
