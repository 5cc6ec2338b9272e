#pragma once
// Tags by the thousand: sets of tags generated from a rule instead of listed one by one (scenario key
// `tag_sets`, io/scenario_yaml.h). A set is either
//  - a grid: every point min + (i, j, k)·step in a box (a plane or a line when a side has zero length), all
//    tags with one orientation; or
//  - surface tags: the scene's planar facets selected by material and/or mesh (object) name (shell patterns,
//    fnmatch) and optionally by the direction they face, sampled on a lattice of `step_m` in the facet's plane,
//    centred on the facet (a face narrower than a step, e.g. a shelf's front edge, gets one row along its middle),
//    and moved `offset_m` off the surface along its normal; optionally only those inside a box (`within`). A tag's local +X is the facet normal (it faces
//    out, like an antenna's boresight), its local Z the plane's "up" (world Z projected into the plane; for a
//    horizontal facet the world Y), so a tag polarized along local Z on a rack front is vertical.
// Names come from a pattern: "{i}" is the running index in the set; a grid also has "{ix}", "{iy}", "{iz}"; a
// pattern without "{i}"/"{ix}" gets "_{i}" appended.
// Everything is in a fixed order (grid: x fastest, then y, then z; surfaces: facet index, then lattice row
// and column), so the same scenario always gives the same tags. Throws InputError naming the set on bad
// sizes (step ≤ 0, more than kMaxGeneratedTags tags) and on a selection that matches no facet.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry.h"
#include "core/reader.h"
#include "core/scenario.h"
#include "raytrace/scene.h"

namespace rfidray::io {

// At most this many tags from all sets of one scenario (each TagSpec is a few hundred bytes).
inline constexpr size_t kMaxGeneratedTags = 2'000'000;

struct TagGrid {
  Vec3 min = Vec3::Zero(), max = Vec3::Zero();
  double step_m = 0.1;
};

struct SurfaceSelection {
  std::string material;            // fnmatch pattern on the radio material name; "" = any
  std::string mesh;                // fnmatch pattern on the mesh (OBJ object) name; "" = any
  std::optional<Vec3> facing;      // only facets whose normal is within facing_tolerance_deg of this
  double facing_tolerance_deg = 10.0;
  std::optional<std::pair<Vec3, Vec3>> within;  // only tags inside this box (min, max corners)
  double offset_m = 0.05;          // distance of the tags from the surface, along its normal
  double step_m = 0.2;
};

struct TagSetSpec {
  std::string name_pattern = "tag_{i}";
  TagParams tag;                   // radio keys of every tag of the set
  std::optional<TagGrid> grid;     // exactly one of grid and surface
  std::optional<SurfaceSelection> surface;
  Quat orientation = Quat::Identity();  // grid tags
  int source_line = 0;
  std::string field = "tag_sets[0]";    // for messages
};

// The points of a grid, x fastest, then y, then z; `counts` (if given) receives the points per axis.
// Throws InputError (naming `field`) when step ≤ 0 or the grid would hold more than max_points.
std::vector<Vec3> grid_points(const TagGrid& grid, const std::string& field, size_t max_points,
                              std::array<size_t, 3>* counts = nullptr);

// A tag name from a pattern ({i}, {ix}, {iy}, {iz}).
std::string tag_name(const std::string& pattern, size_t i, size_t ix = 0, size_t iy = 0, size_t iz = 0);

// The tags of one set (fixed motion). `scene` is needed for surface sets only (may be null for grids).
std::vector<TagSpec> generate_tags(const TagSetSpec& set, const Scene* scene, size_t max_tags = kMaxGeneratedTags);

// The orientation of a tag on a surface of normal `n` (unit): local +X = n, local Z = the plane's up.
Quat surface_orientation(const Vec3& n);

}  // namespace rfidray::io
