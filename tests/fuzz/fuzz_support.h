#pragma once
// Shared by the libFuzzer harnesses (tests/fuzz/fuzz_*.cpp): the invariants every parser must keep on any
// input, and a scratch directory for the parsers that read files.
//
// Invariants (a violation aborts, which libFuzzer reports as a finding with the input saved):
//  - the only exception that may leave a parser is rfidray::InputError, and its message names where the
//    problem is: it contains the input's file name (`require_located`);
//  - no NaN or infinity escapes into a parsed value (`require_finite`).
// Sanitizers add the rest (memory errors, leaks, UB). Not thread-safe: libFuzzer runs one input at a time.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "core/error.h"
#include "core/geometry.h"

namespace rfidray::fuzz {

[[noreturn]] inline void violation(const std::string& what) {
  std::fprintf(stderr, "fuzz invariant violated: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

inline void require_finite(double value, const char* what) {
  if (!std::isfinite(value)) violation(std::string(what) + " is not finite");
}
inline void require_finite(const Vec3& v, const char* what) {
  for (int i = 0; i < 3; ++i) require_finite(v[i], what);
}

// A per-process scratch directory (removed at exit); files in it are overwritten by each input.
inline const std::filesystem::path& scratch_dir() {
  static const std::filesystem::path dir = [] {
    std::string pattern = (std::filesystem::temp_directory_path() / "rfidray-fuzz-XXXXXX").string();
    if (!mkdtemp(pattern.data())) violation("cannot create a scratch directory");
    static const std::filesystem::path made = pattern;
    std::atexit([] { std::error_code ec; std::filesystem::remove_all(made, ec); });
    return made;
  }();
  return dir;
}

inline std::filesystem::path write_scratch(const std::string& name, std::string_view bytes) {
  const std::filesystem::path path = scratch_dir() / name;
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  if (!out) violation("cannot write " + path.string());
  return path;
}

// Runs `parse`; an InputError must name `location` (a file name); any other exception is a finding.
// Returns true when `parse` completed.
template <typename F>
bool run_guarded(const std::string& location, F&& parse) {
  try {
    parse();
    return true;
  } catch (const InputError& e) {
    const std::string message = e.what();
    if (message.find(location) == std::string::npos)
      violation("InputError does not name '" + location + "': " + message.substr(0, 400));
    if (message.size() > 4096) violation("InputError message of " + std::to_string(message.size()) + " bytes");
  } catch (const std::exception& e) {
    violation(std::string("exception other than InputError: ") + e.what());
  }
  return false;
}

}  // namespace rfidray::fuzz
