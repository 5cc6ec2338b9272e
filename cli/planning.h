#pragma once
// What `rfidray coverage` and `rfidray place` share: the options that say where to evaluate (a plane, a box or
// the scenario's tags), loading the scenario (or world), its scene and channel once, and the coverage of a
// set of antennas over the cells sharded over MPI ranks (parallel/ranks.h) and gathered on rank 0.
#include <CLI/CLI.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/channel.h"
#include "core/scenario.h"
#include "core/simulation.h"
#include "planning/coverage_map.h"
#include "io/map_plot.h"
#include "io/world_source.h"
#include "raytrace/scene.h"

namespace rfidray::cli {

struct PlanningOptions {
  std::string scenario;
  io::WorldSourceOptions world;
  std::string channel, model;
  std::string plane;              // "z=1.2"
  std::string box;                // x0,y0,z0,x1,y1,z1
  std::string extent;             // x0,y0,x1,y1 of the plane (default: the scene's, or the tags')
  bool tags = false;              // the scenario's tags (listed and generated) are the cells
  std::string tag_filter;         // with tags: only tags whose name matches this shell pattern
  // The cells' tag as an antenna (core/tag_antenna.h, io/tag_antenna_spec.h text forms); "" keeps the scenario's.
  std::string tag_antenna, tag_chip, tag_backing;
  std::string view = "top";       // maps: top (x, y) | side (along the cells' longer horizontal extent, and z)
  double step_m = 0.1;
  double pass_step_s = 0.0;
  bool three_d = false;           // localization bound in 3-D
  int threads = 0;
  std::string output_dir = "out/coverage";
  bool no_png = false, quiet = false, progress = false;
};

// Adds the options above (except output) to a subcommand.
void add_planning_options(CLI::App& cmd, PlanningOptions& o);

struct Planning {
  Scenario scenario;
  SceneMotion motion;
  std::shared_ptr<const Scene> scene;      // null when the scenario has no meshes
  std::unique_ptr<Channel> channel;
  std::unique_ptr<Channel> ideal;
  std::vector<std::string> channel_report;
  planning::CoverageCells cells;
  bool grid = false;                       // cells on a plane grid (nx × ny, x fastest)
  size_t nx = 0, ny = 0;
  double plane_z = 0.0;                    // plane height, or the tags' median height (floor plan cut)
  std::string source;                      // scenario or world file
  int threads = 1;                         // OpenMP threads per process: --threads, or what this process can start
};

// Loads everything; `candidates` (place) are extra antennas whose links `channel: auto` may sample.
Planning prepare_planning(const PlanningOptions& o);

// Coverage of `antennas` (indices into scenario.antennas) over the cells, each rank computing its share of the
// cells; the result (index-aligned with `antennas`) on rank 0 only (empty elsewhere). Progress on rank 0.
// `information`: also each pass's position information (planning::CoverageValues::information); `validity`: each
// cell's validity verdict (planning::CoverageValues::outside_validity, validity_error; NaN without).
std::vector<planning::CoverageValues> sharded_coverage(const Planning& p, const std::vector<size_t>& antennas,
                                                 const PlanningOptions& o, const std::string& label,
                                                 bool information = false, bool validity = false);

// The floor map of one quantity, its walls (scene cut at plane_z), antennas and robot paths filled.
io::FloorMap floor_map(const Planning& p, const std::vector<size_t>& antennas, const std::vector<double>& value,
                       const std::string& title, const std::string& label, const std::string& view = "top");

// Creates the output directory (InputError on failure).
void make_output_dir(const std::string& dir);

}  // namespace rfidray::cli
