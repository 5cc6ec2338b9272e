#pragma once
// A progress line on stderr for long runs: "coverage: 41% 1.23e+05 links/s, ETA 12 s", redrawn in place at most
// four times a second, and only once the run has lasted 2 s (short runs print nothing). Off with -q, and off
// when stderr is not a terminal unless forced (--progress), so logs and pipes stay clean.
// advance() is thread-safe (OpenMP workers call it); the line is drawn by whichever caller gets the lock.
#include <atomic>
#include <chrono>
#include <cstddef>
#include <mutex>
#include <string>

namespace rfidray::cli {

class ProgressLine {
 public:
  // enabled: the caller's decision (see enabled_for); total: units of work; unit: what a unit is ("links").
  ProgressLine(std::string label, size_t total, std::string unit, bool enabled);
  ~ProgressLine();  // finish()
  void advance(size_t n);
  // Ends the line (clears it) if one was drawn.
  void finish();

  // -q → off; --progress → on; else on iff stderr is a terminal.
  static bool enabled_for(bool quiet, bool forced);

 private:
  void draw(size_t done, bool final);
  std::string label_, unit_;
  size_t total_;
  bool enabled_;
  std::atomic<size_t> done_{0};
  std::mutex mutex_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  bool drawn_ = false;
};

}  // namespace rfidray::cli
