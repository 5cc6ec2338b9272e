#pragma once
// Maps over the floor plan through gnuplot (pngcairo): a value per cell as a heatmap (cells on a grid) or as
// coloured points (scattered cells, e.g. tags on rack faces, seen from above), the scene cut at a height as
// black lines, antennas as markers with their boresight, robot paths as lines, and a colour bar with units.
// The data and the script are written beside the PNG (<name>.dat, <name>.gp), as io/plot.h does.
// Throws std::runtime_error when gnuplot is missing or fails. Not thread-safe (runs a process).
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry.h"
#include "raytrace/scene.h"

namespace rfidray::io {

struct MapAntenna {
  std::string name;
  Vec3 position = Vec3::Zero();
  Vec3 boresight = Vec3::UnitX();  // world direction of the antenna's +X
};

struct FloorMap {
  std::string title, value_label;     // value_label: the colour bar's, with units
  std::string x_label = "x (m)", y_label = "y (m)";
  bool grid = true;                   // true: x, y are the centres of an nx × ny grid (x fastest): drawn as an image
  size_t nx = 0, ny = 0;
  std::vector<double> x, y, value;    // NaN: no value (left blank)
  std::optional<std::pair<double, double>> range;  // colour range; default: the data's
  bool reversed_palette = false;      // small is good (e.g. a localization bound): green low, red high
  bool log_scale = false;             // colour by log10 (values spanning decades, e.g. a bound)
  std::vector<std::array<double, 4>> walls;        // segments x0, y0, x1, y1
  std::vector<MapAntenna> antennas;
  std::vector<std::vector<Vec3>> paths;            // polylines (robot passes)
};

// The scene's triangles cut by the horizontal plane z = height: one segment per crossing triangle.
std::vector<std::array<double, 4>> scene_cut(const Scene& scene, double height_m);

void write_map_png(const std::filesystem::path& png, const FloorMap& map, int width_px = 1000);

}  // namespace rfidray::io
