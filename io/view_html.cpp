#include "io/view_html.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "core/error.h"
#include "core/units.h"
#include "io/atomic_file.h"

namespace rfidray::io {
namespace {

// Millimetres are plenty for a picture, and keep the page small (shortest round-trip digits).
double mm(double v) { return std::round(v * 1000.0) / 1000.0; }
nlohmann::json point(const Vec3& p) { return {mm(p.x()), mm(p.y()), mm(p.z())}; }

// Fixed colours for the built-in radio materials (core/material.cpp), a palette for the others.
std::string material_colour(const std::string& name, size_t index) {
  static const std::map<std::string, std::string> fixed = {
      {"metal", "#8a9bb0"}, {"concrete", "#b9b6ad"}, {"brick", "#b5653a"},
      {"plasterboard", "#e6e0cf"}, {"wood", "#a87b4f"}, {"glass", "#7fd0e0"}};
  static const char* palette[] = {"#6c8ebf", "#82b366", "#d6b656", "#ae4132", "#9673a6", "#d79b00", "#10739e"};
  const auto it = fixed.find(name);
  return it != fixed.end() ? it->second : palette[index % std::size(palette)];
}

std::string read_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in || !std::filesystem::is_regular_file(path))
    throw InputError(path.string() + ": cannot read three.js (" +
                     (std::filesystem::exists(path) ? "unreadable" : "no such file") +
                     "): `rfidray view` inlines Debian's three.js; install it with: apt-get install libjs-three");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Text inside <script>: a literal "</script" (any case) would end the element early. It can only stand in a
// string literal (of JSON or JavaScript), where "<\/" means the same.
std::string script_safe(std::string text) {
  std::string lower = text;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  for (size_t at = lower.rfind("</script"); at != std::string::npos; at = at ? lower.rfind("</script", at - 1) : std::string::npos)
    text.replace(at, 2, "<\\/");
  return text;
}

nlohmann::json scene_json(const ViewInput& in) {
  nlohmann::json mats = nlohmann::json::array();
  if (!in.scene) return mats;
  const Scene& s = *in.scene;
  // One flat triangle list per material: merged geometry, one draw call per material.
  std::vector<std::vector<double>> positions(s.materials().size());
  std::vector<size_t> triangles(s.materials().size(), 0);
  for (uint32_t t = 0; t < s.triangle_count(); ++t) {
    const uint32_t m = s.material_of(t);
    for (const Vec3& c : s.corners(t))
      for (int k = 0; k < 3; ++k) positions[m].push_back(mm(c[k]));
    ++triangles[m];
  }
  for (size_t m = 0; m < s.materials().size(); ++m) {
    if (triangles[m] == 0) continue;
    mats.push_back({{"name", s.materials()[m].name},
                    {"colour", material_colour(s.materials()[m].name, m)},
                    {"triangles", triangles[m]},
                    {"positions", positions[m]}});
  }
  return mats;
}

nlohmann::json data_json(const ViewInput& in) {
  nlohmann::json j;
  j["title"] = in.title;
  j["level"] = in.level;
  j["materials"] = scene_json(in);
  j["antennas"] = nlohmann::json::array();
  for (const ViewMarker& a : in.antennas) {
    const Vec3 boresight = a.pose.orientation * Vec3::UnitX();
    j["antennas"].push_back({{"name", a.name}, {"position", point(a.pose.position)},
                             {"boresight", {boresight.x(), boresight.y(), boresight.z()}}});
  }
  j["tags"] = nlohmann::json::array();
  for (const ViewMarker& t : in.tags) j["tags"].push_back({{"name", t.name}, {"position", point(t.pose.position)}});
  j["links"] = nlohmann::json::array();
  j["paths"] = nlohmann::json::array();
  for (size_t l = 0; l < in.links.size(); ++l) {
    const ViewLink& link = in.links[l];
    const std::complex<double> h = sum_paths(link.paths);
    j["links"].push_back({{"antenna", link.antenna}, {"tag", link.tag}, {"frequency_hz", link.frequency_hz},
                          {"h", {h.real(), h.imag()}}, {"paths", link.paths.size()}});
    // Relative power: each path's |contribution|² against the link's strongest, in dB (a zero contribution
    // is floored at −300 dB so the page never sees −inf).
    double strongest = 0.0;
    for (const Path& p : link.paths) strongest = std::max(strongest, std::norm(p.contribution));
    for (const Path& p : link.paths) {
      const double rel_db =
          strongest > 0.0 ? std::max(-300.0, linear_to_db(std::max(std::norm(p.contribution), 1e-300) / strongest)) : -300.0;
      nlohmann::json pts = nlohmann::json::array({point(link.from)});
      if (p.kind == PathKind::kReflection) pts.push_back(point(p.point));
      pts.push_back(point(link.to));
      j["paths"].push_back({{"link", l},
                            {"kind", to_string(p.kind)},
                            {"points", pts},
                            {"length_m", p.length_m},
                            {"material", p.material},
                            {"crossings", p.crossings},
                            {"coefficient", {p.coefficient.real(), p.coefficient.imag()}},
                            {"relative_db", rel_db}});
    }
  }
  return j;
}

constexpr const char* kStyle = R"CSS(
html, body { margin: 0; height: 100%; overflow: hidden; font: 13px/1.35 system-ui, sans-serif; background: #1d2127; color: #e8e8e8; }
#view { position: absolute; left: 0; top: 0; right: 440px; bottom: 0; }
#side { position: absolute; top: 0; right: 0; width: 440px; bottom: 0; overflow: auto; background: #262b33; padding: 8px 10px; box-sizing: border-box; }
h1 { font-size: 15px; margin: 0 0 4px; } h2 { font-size: 13px; margin: 10px 0 4px; }
.swatch { display: inline-block; width: 12px; height: 12px; margin-right: 6px; vertical-align: -2px; border: 1px solid #0006; }
#powerbar { height: 10px; background: linear-gradient(to right, hsl(240,90%,55%), hsl(120,90%,50%), hsl(0,90%,55%)); }
.scale { display: flex; justify-content: space-between; font-size: 11px; color: #aaa; }
table { border-collapse: collapse; width: 100%; font-size: 11px; } td, th { padding: 1px 3px; text-align: right; white-space: nowrap; }
th { color: #aaa; font-weight: normal; } td.l, th.l { text-align: left; }
tr.path:hover, tr.path.hot { background: #3b4452; cursor: default; }
#tip { position: absolute; pointer-events: none; background: #000c; padding: 5px 7px; border-radius: 4px; display: none; white-space: pre; font-size: 12px; }
#nowebgl { margin: 40px auto; max-width: 520px; padding: 12px 16px; background: #3a2a1c; border: 1px solid #c98a3a; border-radius: 4px; font-size: 14px; }
#help { position: absolute; left: 8px; bottom: 6px; color: #999; font-size: 11px; }
)CSS";

constexpr const char* kScript = R"JS(
(function () {
  'use strict';
  var body = document.body;
  var data = JSON.parse(document.getElementById('rfidray-data').textContent);
  var view = document.getElementById('view'), tip = document.getElementById('tip');
  function fmt(v, d) { return Number(v).toFixed(d); }
  function powerColour(db) {  // 0 dB (strongest of its link) red ... -40 dB and below blue
    var t = Math.min(1, Math.max(0, -db / 40));
    return new THREE.Color().setHSL((240 * t) / 360, 0.9, 0.55);
  }
  function coefText(c, digits) {
    var mag = Math.hypot(c[0], c[1]), deg = Math.atan2(c[1], c[0]) * 180 / Math.PI;
    return fmt(mag, digits) + '\u2220' + fmt(deg, digits > 3 ? 2 : 0) + '\u00b0';
  }

  // WebGL may be missing (turned off, a blocklisted GPU, headless Chromium without --enable-unsafe-swiftshader).
  // Then the view says so and why, and the side panel (materials, paths) is still filled: never a blank page.
  // The probe comes first because three.js reports a failed context through console.error before throwing.
  function createRenderer() {
    var gl = null;
    try {
      var probe = document.createElement('canvas');
      gl = window.WebGLRenderingContext &&
        (probe.getContext('webgl2') || probe.getContext('webgl') || probe.getContext('experimental-webgl'));
    } catch (e) { gl = null; }
    if (!gl) return null;
    try { return new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true }); } catch (e) { return null; }
  }
  var renderer = createRenderer();
  if (renderer) {
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setSize(view.clientWidth, view.clientHeight);
    renderer.setClearColor(0x1d2127);
    view.appendChild(renderer.domElement);
  } else {
    var note = document.createElement('div');
    note.id = 'nowebgl';
    note.textContent = 'This browser cannot draw the 3-D view: WebGL is not available (it may be turned off in ' +
      'the browser\'s settings, or the graphics driver is blocklisted; headless Chromium needs ' +
      '--enable-unsafe-swiftshader). The materials and the table of paths on the right are complete; open the ' +
      'page in a browser with WebGL to see the scene.';
    view.appendChild(note);
    body.dataset.webgl = 'no';
  }
  var scene = new THREE.Scene();
  scene.add(new THREE.AmbientLight(0xffffff, 0.55));
  var sun = new THREE.DirectionalLight(0xffffff, 0.6);
  sun.position.set(0.4, -0.6, 1.0);
  scene.add(sun);

  var box = new THREE.Box3();
  // Scene: one merged mesh per radio material.
  var legend = document.getElementById('materials');
  data.materials.forEach(function (m) {
    var g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(m.positions, 3));
    g.computeVertexNormals();
    g.computeBoundingBox();
    box.union(g.boundingBox);
    var mat = new THREE.MeshLambertMaterial({ color: m.colour, side: THREE.DoubleSide, transparent: true,
                                              opacity: 0.45, depthWrite: false });
    var mesh = new THREE.Mesh(g, mat);
    mesh.userData.info = 'material ' + m.name + '\n' + m.triangles + ' triangles';
    scene.add(mesh);
    var li = document.createElement('div');
    li.innerHTML = '<span class="swatch" style="background:' + m.colour + '"></span>' + m.name + ' (' + m.triangles + ' triangles)';
    legend.appendChild(li);
  });
  if (data.materials.length === 0) legend.textContent = 'no geometry';
  data.antennas.forEach(function (a) { box.expandByPoint(new THREE.Vector3().fromArray(a.position)); });
  data.tags.forEach(function (t) { box.expandByPoint(new THREE.Vector3().fromArray(t.position)); });
  if (box.isEmpty()) box.set(new THREE.Vector3(-1, -1, -1), new THREE.Vector3(1, 1, 1));
  var centre = box.getCenter(new THREE.Vector3());
  var size = Math.max(box.getSize(new THREE.Vector3()).length(), 1.0);

  var pickable = [];
  // Antennas: a box and the boresight arrow (local +X).
  data.antennas.forEach(function (a) {
    var p = new THREE.Vector3().fromArray(a.position), d = new THREE.Vector3().fromArray(a.boresight).normalize();
    var s = size * 0.012;
    var m = new THREE.Mesh(new THREE.BoxGeometry(s, s, s), new THREE.MeshLambertMaterial({ color: 0xffffff }));
    m.position.copy(p);
    m.userData.info = 'antenna ' + a.name + '\n(' + a.position.map(function (v) { return fmt(v, 3); }).join(', ') + ')';
    scene.add(m); pickable.push(m);
    scene.add(new THREE.ArrowHelper(d, p, size * 0.08, 0xffffff, size * 0.02, size * 0.012));
  });
  // Tags.
  data.tags.forEach(function (t) {
    var m = new THREE.Mesh(new THREE.SphereGeometry(size * 0.005, 12, 8), new THREE.MeshLambertMaterial({ color: 0x39e07a }));
    m.position.fromArray(t.position);
    m.userData.info = 'tag ' + t.name + '\n(' + t.position.map(function (v) { return fmt(v, 3); }).join(', ') + ')';
    scene.add(m); pickable.push(m);
  });
  // Paths: one line each, coloured by power relative to the strongest path of its link; blocked ones dashed.
  var lines = [], rows = [];
  var table = document.getElementById('paths');
  data.paths.forEach(function (p, i) {
    var link = data.links[p.link];
    var g = new THREE.BufferGeometry().setFromPoints(p.points.map(function (q) { return new THREE.Vector3().fromArray(q); }));
    var colour = powerColour(p.relative_db);
    var mat = p.kind === 'blocked'
      ? new THREE.LineDashedMaterial({ color: colour, dashSize: size * 0.01, gapSize: size * 0.006 })
      : new THREE.LineBasicMaterial({ color: colour });
    var line = new THREE.Line(g, mat);
    if (p.kind === 'blocked') line.computeLineDistances();
    line.userData.colour = colour;
    line.userData.index = i;
    line.userData.info = 'path ' + i + ': ' + p.kind + (p.material ? ' (' + p.material + ')' : '') +
      '\n' + data.antennas[link.antenna].name + ' \u2192 ' + data.tags[link.tag].name +
      '\nlength ' + fmt(p.length_m, 4) + ' m' +
      '\ncoefficient ' + coefText(p.coefficient, 5) +
      (p.kind === 'blocked' ? '\ncrossings ' + p.crossings : '') +
      '\npower ' + fmt(p.relative_db, 1) + ' dB (vs strongest of link)';
    scene.add(line); lines.push(line); pickable.push(line);
    var tr = document.createElement('tr');
    tr.className = 'path';
    tr.dataset.index = i;
    tr.innerHTML = '<td>' + i + '</td><td class="l">' + data.antennas[link.antenna].name + '\u2192' + data.tags[link.tag].name +
      '</td><td class="l">' + p.kind + '</td><td>' + fmt(p.length_m, 2) + '</td><td class="l">' + (p.material || '') +
      '</td><td>' + coefText(p.coefficient, 3) + '</td><td><span class="swatch" style="background:#' + colour.getHexString() +
      '"></span>' + fmt(p.relative_db, 1) + '</td>';
    tr.addEventListener('mouseenter', function () { highlight(i); });
    tr.addEventListener('mouseleave', function () { highlight(-1); });
    table.appendChild(tr); rows.push(tr);
  });
  document.getElementById('summary').textContent = data.level + ': ' + data.links.length + ' links, ' +
    data.paths.length + ' paths, ' + data.antennas.length + ' antennas, ' + data.tags.length + ' tags';

  var camera = new THREE.PerspectiveCamera(45, view.clientWidth / view.clientHeight, size * 0.001, size * 20);
  camera.up.set(0, 0, 1);  // rfidray's world is Z up
  camera.position.copy(centre).add(new THREE.Vector3(0.45, -0.75, 0.55).multiplyScalar(size));
  function render() { if (renderer) renderer.render(scene, camera); }
  function highlight(index) {
    lines.forEach(function (l, i) {
      l.material.color.copy(index < 0 || i === index ? l.userData.colour : new THREE.Color(0x444444));
    });
    rows.forEach(function (r, i) { r.classList.toggle('hot', i === index); });
    render();
  }
  body.dataset.paths = String(lines.length);
  if (!renderer) {
    if (body.dataset.status !== 'error') body.dataset.status = 'no-webgl';
    return;
  }
  var controls = new THREE.OrbitControls(camera, renderer.domElement);
  controls.target.copy(centre);
  controls.update();
  controls.addEventListener('change', render);
  window.addEventListener('resize', function () {
    camera.aspect = view.clientWidth / view.clientHeight;
    camera.updateProjectionMatrix();
    renderer.setSize(view.clientWidth, view.clientHeight);
    render();
  });
  var raycaster = new THREE.Raycaster();
  raycaster.linePrecision = size * 0.004;  // r111; later releases read params.Line.threshold
  raycaster.params.Line = { threshold: size * 0.004 };
  renderer.domElement.addEventListener('mousemove', function (e) {
    var r = renderer.domElement.getBoundingClientRect();
    var mouse = new THREE.Vector2(((e.clientX - r.left) / r.width) * 2 - 1, -((e.clientY - r.top) / r.height) * 2 + 1);
    raycaster.setFromCamera(mouse, camera);
    var hit = raycaster.intersectObjects(pickable)[0];
    if (!hit) { tip.style.display = 'none'; return; }
    tip.textContent = hit.object.userData.info;
    tip.style.left = (e.clientX + 14) + 'px';
    tip.style.top = (e.clientY + 10) + 'px';
    tip.style.display = 'block';
  });
  render();
  // #hover=N moves the mouse over the middle of path N's first leg (for tests: the tooltip must name a path).
  var hover = /hover=(\d+)/.exec(location.hash);
  if (hover && data.paths[+hover[1]]) {
    var pts = data.paths[+hover[1]].points;
    var mid = new THREE.Vector3().fromArray(pts[0]).lerp(new THREE.Vector3().fromArray(pts[1]), 0.5).project(camera);
    var rect = renderer.domElement.getBoundingClientRect();
    renderer.domElement.dispatchEvent(new MouseEvent('mousemove', {
      clientX: rect.left + (mid.x + 1) / 2 * rect.width, clientY: rect.top + (1 - mid.y) / 2 * rect.height }));
  }
  if (body.dataset.status !== 'error') body.dataset.status = 'ready';
})();
)JS";

}  // namespace

std::pair<std::string, std::string> read_three_js(const ThreeJsFiles& files) {
  return {read_file(files.three), read_file(files.orbit_controls)};
}

size_t view_path_count(const ViewInput& input) {
  size_t n = 0;
  for (const ViewLink& l : input.links) n += l.paths.size();
  return n;
}

std::string view_html(const ViewInput& input, const std::string& three_js, const std::string& orbit_controls_js) {
  const nlohmann::json data = data_json(input);
  // HTML-escape the title (it comes from a file name).
  std::string title;
  for (char c : input.title) {
    if (c == '<') title += "&lt;";
    else if (c == '>') title += "&gt;";
    else if (c == '&') title += "&amp;";
    else if (c == '"') title += "&quot;";
    else title += c;
  }
  std::ostringstream out;
  out << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>rfidray view: " << title
      << "</title>\n<style>" << kStyle << "</style>\n"
      // Uncaught errors and console.error calls anywhere (three.js included) are counted on <body>, so a
      // headless browser can read them back.
      << "<script>(function () { function count() { var b = document.body || document.documentElement;"
         " b.dataset.errors = String(Number(b.dataset.errors || 0) + 1); b.dataset.status = 'error'; }"
         " window.addEventListener('error', count); var log = console.error;"
         " console.error = function () { count(); return log.apply(console, arguments); }; })();</script>\n"
      << "</head>\n<body data-status=\"loading\" data-errors=\"0\" data-paths=\"0\">\n"
      << "<div id=\"view\"></div><div id=\"tip\"></div>\n"
      << "<div id=\"help\">drag: orbit · right-drag: pan · wheel: zoom · hover a path for its length, material and "
         "coefficient</div>\n"
      << "<div id=\"side\"><h1>" << title << "</h1><div id=\"summary\"></div>\n"
      << "<h2>Radio materials</h2><div id=\"materials\"></div>\n"
      << "<h2>Path power, relative to the strongest path of its link</h2><div id=\"powerbar\"></div>"
         "<div class=\"scale\"><span>&le; &minus;40 dB</span><span>&minus;20 dB</span><span>0 dB</span></div>\n"
      << "<h2>Paths</h2><table><thead><tr><th>#</th><th class=\"l\">link</th><th class=\"l\">kind</th><th>m</th>"
         "<th class=\"l\">material</th><th>coefficient</th><th>dB</th></tr></thead><tbody id=\"paths\"></tbody>"
         "</table></div>\n"
      << "<script id=\"rfidray-data\" type=\"application/json\">" << script_safe(data.dump()) << "</script>\n"
      << "<script>\n" << script_safe(three_js) << "\n</script>\n"
      << "<script>\n" << script_safe(orbit_controls_js) << "\n</script>\n"
      << "<script>" << kScript << "</script>\n</body>\n</html>\n";
  return out.str();
}

void write_view_html(const std::filesystem::path& path, const ViewInput& input, const ThreeJsFiles& files) {
  const auto [three, orbit] = read_three_js(files);
  const std::string page = view_html(input, three, orbit);
  write_file_atomic(path, [&](std::ostream& out) { out << page; }, "view HTML (check -o FILE)");
}

}  // namespace rfidray::io
