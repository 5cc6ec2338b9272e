#pragma once
// PNG charts through gnuplot (Debian package gnuplot-nox, pngcairo terminal). The data and the script are
// written beside the PNG (<name>.dat, <name>.gp) so every chart can be re-made or restyled by hand.
#include <filesystem>
#include <string>
#include <vector>

namespace rfidray::io {

struct Series {
  std::string title;
  std::vector<double> x, y;
  std::string style = "lines";  // gnuplot style: "lines", "points", "linespoints", "steps"
  std::vector<std::string> labels;  // optional: a text beside each point
};

struct Panel {
  std::string title, xlabel, ylabel;
  std::vector<Series> series;
  bool log_x = false, log_y = false;
};

// Writes `panels` stacked vertically into one PNG. Throws std::runtime_error when gnuplot is missing or fails.
void write_png(const std::filesystem::path& png, const std::vector<Panel>& panels, int width_px = 1100,
               int panel_height_px = 420);

// Runs gnuplot on a script in its own directory (so relative file names in it resolve there). The script must
// `set output` to partial_png_name(png); that temporary is renamed to `png` when gnuplot succeeds and removed
// when it fails, so `png` is complete or absent. Throws std::runtime_error when gnuplot is missing or fails,
// naming the script.
void run_gnuplot(const std::filesystem::path& script, const std::filesystem::path& png);
// The temporary file name (no directory) a script run by run_gnuplot writes for `png`.
std::string partial_png_name(const std::filesystem::path& png);

// A gnuplot string literal.
std::string gnuplot_quoted(const std::string& s);

}  // namespace rfidray::io
