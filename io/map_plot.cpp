#include "io/map_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <stdexcept>

#include "io/plot.h"

namespace rfidray::io {

std::vector<std::array<double, 4>> scene_cut(const Scene& scene, double z) {
  std::vector<std::array<double, 4>> out;
  for (uint32_t t = 0; t < scene.triangle_count(); ++t) {
    const auto c = scene.corners(t);
    // The crossing points of the edges whose ends lie on opposite sides of the plane (or one end on it).
    std::vector<std::pair<double, double>> pts;
    for (int k = 0; k < 3; ++k) {
      const Vec3& a = c[k];
      const Vec3& b = c[(k + 1) % 3];
      const double da = a.z() - z, db = b.z() - z;
      if ((da < 0.0 && db >= 0.0) || (da >= 0.0 && db < 0.0)) {
        const double s = da / (da - db);
        pts.emplace_back(a.x() + s * (b.x() - a.x()), a.y() + s * (b.y() - a.y()));
      }
    }
    if (pts.size() == 2) out.push_back({pts[0].first, pts[0].second, pts[1].first, pts[1].second});
  }
  return out;
}

namespace {

// "%.6g", or NaN (gnuplot leaves such points out).
void put(std::string& line, double v) {
  char buf[32];
  if (std::isfinite(v))
    std::snprintf(buf, sizeof buf, "%.7g", v);
  else
    std::snprintf(buf, sizeof buf, "NaN");
  line += buf;
}

}  // namespace

void write_map_png(const std::filesystem::path& png, const FloorMap& map, int width_px) {
  std::filesystem::path dat = png, gp = png;
  dat.replace_extension(".dat");
  gp.replace_extension(".gp");
  double lo_x = std::numeric_limits<double>::infinity(), hi_x = -lo_x, lo_y = lo_x, hi_y = -lo_x;
  auto extend = [&](double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    lo_x = std::min(lo_x, x), hi_x = std::max(hi_x, x), lo_y = std::min(lo_y, y), hi_y = std::max(hi_y, y);
  };
  for (size_t i = 0; i < map.x.size(); ++i) extend(map.x[i], map.y[i]);
  for (const auto& w : map.walls) extend(w[0], w[1]), extend(w[2], w[3]);
  for (const auto& a : map.antennas) extend(a.position.x(), a.position.y());
  if (!std::isfinite(lo_x)) lo_x = -1, hi_x = 1, lo_y = -1, hi_y = 1;
  const double pad = 0.03 * std::max({hi_x - lo_x, hi_y - lo_y, 1.0});
  lo_x -= pad, hi_x += pad, lo_y -= pad, hi_y += pad;
  {
    std::ofstream d(dat);
    if (!d) throw std::runtime_error("cannot write " + dat.string());
    std::string line;
    // index 0: the cells
    d << "# x y value\n";
    for (size_t i = 0; i < map.x.size(); ++i) {
      line.clear();
      put(line, map.x[i]);
      line += ' ';
      put(line, map.y[i]);
      line += ' ';
      put(line, i < map.value.size() ? map.value[i] : std::nan(""));
      line += '\n';
      d << line;
      if (map.grid && map.nx > 0 && (i + 1) % map.nx == 0) d << '\n';  // rows of an image
    }
    if (map.x.empty()) d << "NaN NaN NaN\n";
    d << "\n\n# walls: x0 y0 x1 y1\n";  // index 1
    for (const auto& w : map.walls) {
      line.clear();
      for (int k = 0; k < 4; ++k) put(line, w[k]), line += k < 3 ? ' ' : '\n';
      d << line;
    }
    if (map.walls.empty()) d << "NaN NaN NaN NaN\n";
    d << "\n\n# antennas: x y dx dy name\n";  // index 2
    const double arrow = 0.06 * std::max(hi_x - lo_x, hi_y - lo_y);
    for (const auto& a : map.antennas) {
      Vec3 b = a.boresight;
      b.z() = 0.0;
      if (b.norm() > 1e-9) b = b.normalized() * arrow;
      line.clear();
      put(line, a.position.x()), line += ' ', put(line, a.position.y()), line += ' ', put(line, b.x()), line += ' ',
          put(line, b.y());
      d << line << ' ' << gnuplot_quoted(a.name) << '\n';
    }
    if (map.antennas.empty()) d << "NaN NaN NaN NaN \"\"\n";
    d << "\n\n# paths: x y\n";  // index 3
    for (const auto& p : map.paths) {
      for (const Vec3& v : p) {
        line.clear();
        put(line, v.x()), line += ' ', put(line, v.y()), line += '\n';
        d << line;
      }
      d << '\n';
    }
    if (map.paths.empty()) d << "NaN NaN\n";
    if (!d) throw std::runtime_error("cannot write " + dat.string());
  }
  const double aspect = (hi_y - lo_y) / (hi_x - lo_x);
  const int height_px = std::clamp(static_cast<int>(width_px * aspect) + 80, 300, 2400);
  std::ofstream g(gp);
  if (!g) throw std::runtime_error("cannot write " + gp.string());
  const std::string data = gnuplot_quoted(dat.filename().string());
  g << "set terminal pngcairo size " << width_px << "," << height_px << " font 'sans,10'\n";
  g << "set output " << gnuplot_quoted(partial_png_name(png)) << "\n";
  g << "set termoption noenhanced\n";  // names like pole_4_0 stay as written (no subscripts)
  g << "set title " << gnuplot_quoted(map.title) << "\n";
  g << "set xlabel " << gnuplot_quoted(map.x_label) << "\nset ylabel " << gnuplot_quoted(map.y_label)
    << "\nset size ratio -1\nset key off\n";
  g << "set xrange [" << lo_x << ":" << hi_x << "]\nset yrange [" << lo_y << ":" << hi_y << "]\n";
  g << "set cblabel " << gnuplot_quoted(map.value_label) << "\n";
  if (map.range) {
    g << "set cbrange [" << map.range->first << ":" << map.range->second << "]\n";
  } else {
    // A constant map (e.g. no multipath anywhere) still gets a colour bar around its value.
    double lo = INFINITY, hi = -INFINITY;
    for (double v : map.value)
      if (std::isfinite(v) && (!map.log_scale || v > 0.0)) lo = std::min(lo, v), hi = std::max(hi, v);
    if (std::isfinite(lo) && !(hi > lo)) {
      const double pad = map.log_scale ? 0.5 * lo : std::max(1e-3, 0.1 * std::abs(lo));
      g << "set cbrange [" << lo - pad << ":" << hi + pad << "]\n";
    }
  }
  if (map.log_scale) g << "set logscale cb\n";
  // Red (poor) → yellow → green (good); reversed when small values are good.
  g << (map.reversed_palette ? "set palette defined (0 '#1a9850', 0.5 '#fee08b', 1 '#d73027')\n"
                             : "set palette defined (0 '#d73027', 0.5 '#fee08b', 1 '#1a9850')\n");
  g << "set style fill solid\n";
  g << "plot " << data << " index 0 using 1:2:3 "
    << (map.grid ? "with image" : "with points pt 7 ps 0.5 lc palette") << ", \\\n";
  g << "  " << data << " index 1 using 1:2:($3-$1):($4-$2) with vectors nohead lw 1 lc rgb 'black', \\\n";
  g << "  " << data << " index 3 using 1:2 with lines lw 1.5 dt 2 lc rgb '#3b4cc0', \\\n";
  g << "  " << data << " index 2 using 1:2:3:4 with vectors head filled lw 2 lc rgb '#3b4cc0', \\\n";
  g << "  " << data << " index 2 using 1:2 with points pt 5 ps 1.4 lc rgb '#3b4cc0', \\\n";
  g << "  " << data << " index 2 using 1:2:5 with labels offset char 1,1 left font ',9' tc rgb '#3b4cc0'\n";
  g.close();
  run_gnuplot(gp, png);
}

}  // namespace rfidray::io
