#include "io/plot.h"

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include <unistd.h>

namespace rfidray::io {
namespace {

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

}  // namespace

void write_png(const std::filesystem::path& png, const std::vector<Panel>& panels, int width_px,
               int panel_height_px) {
  std::filesystem::path dat = png, gp = png;
  dat.replace_extension(".dat");
  gp.replace_extension(".gp");
  {
    // One gnuplot data block per series, separated by two blank lines (addressed with `index`).
    std::ofstream d(dat);
    if (!d) throw std::runtime_error("cannot write " + dat.string());
    d.precision(10);
    for (const Panel& p : panels)
      for (const Series& s : p.series) {
        d << "# " << s.title << "\n";
        for (size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
          d << s.x[i] << ' ' << s.y[i];
          if (!s.labels.empty()) d << ' ' << quoted(i < s.labels.size() ? s.labels[i] : "");
          d << '\n';
        }
        if (s.x.empty()) d << "nan nan\n";  // keep the block so indices stay aligned
        d << "\n\n";
      }
  }
  std::ofstream g(gp);
  if (!g) throw std::runtime_error("cannot write " + gp.string());
  g << "set terminal pngcairo size " << width_px << "," << panel_height_px * static_cast<int>(panels.size())
    << " font 'sans,10'\n";
  g << "set output " << quoted(partial_png_name(png)) << "\n";
  g << "set grid\nset key outside right top\n";
  if (panels.size() > 1) g << "set multiplot layout " << panels.size() << ",1\n";
  int block = 0;
  for (const Panel& p : panels) {
    g << "set title " << quoted(p.title) << "\nset xlabel " << quoted(p.xlabel) << "\nset ylabel "
      << quoted(p.ylabel) << "\n";
    g << (p.log_x ? "set logscale x\n" : "unset logscale x\n") << (p.log_y ? "set logscale y\n" : "unset logscale y\n");
    g << "plot ";
    for (size_t i = 0; i < p.series.size(); ++i) {
      if (i) g << ", ";
      g << quoted(dat.filename().string()) << " index " << block << " using 1:2 with " << p.series[i].style
        << " title " << quoted(p.series[i].title);
      if (!p.series[i].labels.empty())
        g << ", " << quoted(dat.filename().string()) << " index " << block
          << " using 1:2:3 with labels offset char 0.6,0.5 left font ',8' notitle";
      ++block;
    }
    if (p.series.empty()) g << "NaN notitle";
    g << "\n";
  }
  if (panels.size() > 1) g << "unset multiplot\n";
  g.close();
  run_gnuplot(gp, png);
}

std::string partial_png_name(const std::filesystem::path& png) {
  return png.filename().string() + ".tmp-" + std::to_string(::getpid()) + ".png";
}

std::string gnuplot_quoted(const std::string& s) { return quoted(s); }

void run_gnuplot(const std::filesystem::path& gp, const std::filesystem::path& png) {
  const std::string dir = gp.has_parent_path() ? gp.parent_path().string() : ".";
  const std::string cmd = "cd " + quoted(dir) + " && gnuplot " + quoted(gp.filename().string()) + " 2>&1";
  if (std::system("command -v gnuplot > /dev/null 2>&1") != 0)
    throw std::runtime_error("cannot run " + gp.string() + ": gnuplot not found (install it: apt-get install gnuplot-nox)");
  // gnuplot draws into a temporary that is renamed over the PNG only when gnuplot succeeded, so a failed or
  // interrupted plot never leaves a truncated PNG under the final name (io/atomic_file.h does the same for data).
  const std::filesystem::path partial = png.parent_path() / partial_png_name(png);
  std::error_code ec;
  if (std::system(cmd.c_str()) != 0) {
    std::filesystem::remove(partial, ec);
    throw std::runtime_error("gnuplot failed on " + gp.string() + " (its messages are above)");
  }
  std::filesystem::rename(partial, png, ec);
  if (ec) {
    std::filesystem::remove(partial, ec);
    throw std::runtime_error("cannot write " + png.string() + ": " + ec.message());
  }
}

}  // namespace rfidray::io
