#pragma once
// A scratch directory for one test, removed with everything in it when the object goes out of scope (also when
// an assertion fails). Unique per process and name: tests of one executable run in parallel under ctest -j.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <system_error>

#include "tests/support/files.h"

namespace rfidray::testing {

class ScratchDir {
 public:
  explicit ScratchDir(const std::string& name)
      : path_(std::filesystem::temp_directory_path() /
              ("rfidray_" + name + "_" + std::to_string(::getpid()))) {
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  // Named after the running test ("rfidray_<prefix>_<Suite>_<Test>_<pid>").
  static std::string current_test_name(const std::string& prefix) {
    const ::testing::TestInfo* t = ::testing::UnitTest::GetInstance()->current_test_info();
    return t ? prefix + "_" + t->test_suite_name() + "_" + t->name() : prefix;
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::string string() const { return path_.string(); }
  std::filesystem::path operator/(const std::string& file) const { return path_ / file; }
  // Writes `text` to `file` inside the directory; returns its path.
  std::filesystem::path write(const std::string& file, const std::string& text) const {
    return write_file(path_ / file, text);
  }

 private:
  std::filesystem::path path_;
};

// A scratch directory shared by the tests of one program under `name`, made on first use and removed when the
// program exits. Not thread-safe (gtest runs the tests of a program one after the other).
inline const std::filesystem::path& program_scratch_dir(const std::string& name) {
  static std::map<std::string, std::unique_ptr<ScratchDir>> dirs;
  std::unique_ptr<ScratchDir>& dir = dirs[name];
  if (!dir) dir = std::make_unique<ScratchDir>(name);
  return dir->path();
}

}  // namespace rfidray::testing
