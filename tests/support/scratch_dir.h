#pragma once
// A scratch directory for one test, removed with everything in it when the object goes out of scope (also when
// an assertion fails). Unique per process and name: tests of one executable run in parallel under ctest -j.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
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

}  // namespace rfidray::testing
