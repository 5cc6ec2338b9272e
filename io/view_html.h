#pragma once
// The 3-D view of a scene and its traced paths as one self-contained HTML file (`rfidray view`): the scene
// mesh merged into one geometry per radio material (one draw call each) with a legend, antennas with their
// boresight (local +X) arrows, tags, and every path of the chosen links coloured by its power relative to the
// strongest path of its link; hovering a path shows its kind, length, material and coefficient; orbit controls.
// three.js (r111) and its OrbitControls come from Debian's libjs-three and are inlined, so the page needs no
// network. The page lists every path in a table (rows `tr.path`) and reports itself on <body>:
// data-status="ready" | "error" | "no-webgl", data-paths (paths listed), data-errors (uncaught script errors and
// console.error calls). Without WebGL the view shows a message saying so (#nowebgl) and data-webgl="no"; the
// legend and the path table are still filled. Opened as view.html#hover=N it moves the mouse over path N (so a test can read the tooltip).
// Functions are thread-safe (no shared state).
#include <filesystem>
#include <string>
#include <vector>

#include "core/geometry.h"
#include "core/path.h"
#include "raytrace/scene.h"

namespace rfidray::io {

struct ViewMarker {
  std::string name;
  Pose pose;  // antennas: boresight = local +X
};

// One antenna–tag link and its paths (Channel::paths, contribution filled). `from`/`to` are the points the
// paths start and end at (the antenna's phase centre and the tag).
struct ViewLink {
  size_t antenna = 0;  // index into ViewInput::antennas
  size_t tag = 0;      // index into ViewInput::tags
  double frequency_hz = 0.0;
  Vec3 from = Vec3::Zero();
  Vec3 to = Vec3::Zero();
  std::vector<Path> paths;
};

struct ViewInput {
  std::string title;
  std::string level;  // channel level of the paths ("single-bounce", ...)
  const Scene* scene = nullptr;  // may be null (no geometry)
  std::vector<ViewMarker> antennas;
  std::vector<ViewMarker> tags;
  std::vector<ViewLink> links;
};

// Where Debian's libjs-three puts three.js and its orbit controls.
struct ThreeJsFiles {
  std::filesystem::path three = "/usr/share/javascript/three/three.min.js";
  std::filesystem::path orbit_controls = "/usr/share/javascript/three/examples/js/controls/OrbitControls.js";
};

// Reads both files; throws InputError naming the missing file and the package to install (libjs-three).
std::pair<std::string, std::string> read_three_js(const ThreeJsFiles& files = {});

// The page. `three_js` and `orbit_controls_js` are the scripts' text (read_three_js).
std::string view_html(const ViewInput& input, const std::string& three_js, const std::string& orbit_controls_js);

// read_three_js + view_html, written atomically (io/atomic_file.h).
void write_view_html(const std::filesystem::path& path, const ViewInput& input, const ThreeJsFiles& files = {});

// Number of paths the page draws (every path of every link).
size_t view_path_count(const ViewInput& input);

}  // namespace rfidray::io
