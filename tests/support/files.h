#pragma once
// Whole files for tests: read one into a string, write one from a string.
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

namespace rfidray::testing {

// The whole content of a file ("" when it cannot be read).
inline std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Writes `text` to `file` (binary, replacing it), creating its folder; returns the path.
inline std::filesystem::path write_file(const std::filesystem::path& file, const std::string& text) {
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path());
  std::ofstream(file, std::ios::binary) << text;
  return file;
}

}  // namespace rfidray::testing
