#pragma once
// Scenes and link workloads shared by the speed benchmarks (bench_rays, bench_sweep, bench_accuracy).
//
// Scenes: the paper warehouse and parametric warehouses of metal racks at ~10 k, 100 k, 1 M and 5 M triangles.
// Workloads: antenna poses along one aisle (1.0 m high, the pose shared by all tags of a batch, as in
// `rfidray simulate`), tags 5 cm in front of rack faces and 5 cm above a shelf, spread over every row of the
// warehouse (so most links of a big warehouse cross racks, as for a deployment of many tags and few antennas).
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/channel.h"
#include "raytrace/warehouse.h"

namespace rfidray::bench {

struct BenchScene {
  std::string name;
  bool paper = false;      // the paper warehouse (params unused)
  WarehouseParams params;  // parametric otherwise
};

// The scenes of the throughput and scaling charts, smallest first.
inline std::vector<BenchScene> bench_scenes() {
  return {
      {"paper", true, {}},
      {"w10k", false, {.rows = 4, .racks_per_row = 25, .shelves = 5, .tessellation = 1}},
      {"w100k", false, {.rows = 10, .racks_per_row = 25, .shelves = 5, .tessellation = 2}},
      {"w1m", false, {.rows = 20, .racks_per_row = 60, .shelves = 5, .tessellation = 3}},
      {"w5m", false, {.rows = 20, .racks_per_row = 100, .shelves = 5, .tessellation = 5}},
  };
}

// "a,b,,c" → {"a", "b", "c"} (command-line lists).
inline std::vector<std::string> split_commas(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');)
    if (!item.empty()) out.push_back(item);
  return out;
}

inline BenchScene find_bench_scene(const std::string& name) {
  for (const BenchScene& s : bench_scenes())
    if (s.name == name) return s;
  throw std::invalid_argument("unknown bench scene '" + name + "' (paper, w10k, w100k, w1m, w5m)");
}

inline std::vector<TriangleMesh> scene_meshes(const BenchScene& s) {
  return s.paper ? paper_warehouse_meshes() : generate_warehouse(s.params);
}

inline Endpoint isotropic_endpoint(const Vec3& p) {
  Endpoint e;
  e.pose.position = p;
  return e;  // isotropic pattern, linear polarization along z
}

struct Workload {
  std::vector<Endpoint> antennas;  // poses, each shared by all tags of one batch
  std::vector<Endpoint> tags;
  size_t links() const { return antennas.size() * tags.size(); }
};

// Paper warehouse: tags near the paper's ten positions (1 cm steps along the racks), antennas on the robot
// aisle x = −1 m, y −10…8 m.
inline Workload paper_workload(int n_tags, int n_poses) {
  Workload w;
  const double ys[] = {0.57, -1.24, -3.03, -4.82, -6.75, -8.66, -7.70, -3.03, 1.44, 5.95};
  for (int i = 0; i < n_tags; ++i) {
    const bool east = i % 10 < 6;
    const double y = ys[i % 10] + 0.01 * (i / 10 % 50);
    w.tags.push_back(isotropic_endpoint(east ? Vec3(2.90, y, 2.05) : Vec3(-4.85, y, 1.85)));
  }
  for (int k = 0; k < n_poses; ++k)
    w.antennas.push_back(isotropic_endpoint(Vec3(-1.0, -10.0 + 18.0 * k / std::max(1, n_poses - 1), 1.0)));
  return w;
}

// Parametric warehouse: tags on the rack fronts of every row and shelf, antennas along the middle aisle.
inline Workload warehouse_workload(const WarehouseParams& p, int n_tags, int n_poses) {
  Workload w;
  const double pitch = p.rack_length_m + 0.1, row = p.rack_depth_m + p.aisle_m;
  const double length = p.racks_per_row * pitch;
  for (int i = 0; i < n_tags; ++i) {
    const int r = i % p.rows;
    const int s = (i / p.rows) % p.shelves;
    const double y = std::fmod(0.37 * i, length - 0.2) + 0.1;
    w.tags.push_back(isotropic_endpoint(Vec3(r * row + p.aisle_m - 0.05, y, 0.15 + s * p.shelf_spacing_m + 0.05)));
  }
  const int mid = p.rows / 2;
  for (int k = 0; k < n_poses; ++k)
    w.antennas.push_back(isotropic_endpoint(Vec3(mid * row + 0.5 * p.aisle_m, length * (k + 0.5) / n_poses, 1.0)));
  return w;
}

inline Workload scene_workload(const BenchScene& s, int n_tags, int n_poses) {
  return s.paper ? paper_workload(n_tags, n_poses) : warehouse_workload(s.params, n_tags, n_poses);
}

}  // namespace rfidray::bench
