#include "cli/progress.h"

#include <unistd.h>

#include <cstdio>

namespace rfidray::cli {

ProgressLine::ProgressLine(std::string label, size_t total, std::string unit, bool enabled)
    : label_(std::move(label)), unit_(std::move(unit)), total_(total), enabled_(enabled),
      start_(std::chrono::steady_clock::now()), last_draw_(start_) {}

ProgressLine::~ProgressLine() { finish(); }

bool ProgressLine::enabled_for(bool quiet, bool forced) {
  if (quiet) return false;
  return forced || ::isatty(2) == 1;
}

void ProgressLine::advance(size_t n) {
  const size_t done = done_.fetch_add(n) + n;
  if (!enabled_) return;
  std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
  if (!lock.owns_lock()) return;
  const auto now = std::chrono::steady_clock::now();
  if (now - start_ < std::chrono::seconds(2) || now - last_draw_ < std::chrono::milliseconds(250)) return;
  last_draw_ = now;
  draw(done, false);
}

void ProgressLine::draw(size_t done, bool final) {
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double rate = elapsed > 0.0 ? static_cast<double>(done) / elapsed : 0.0;
  const double pct = total_ > 0 ? 100.0 * static_cast<double>(done) / static_cast<double>(total_) : 100.0;
  char eta[64] = "";
  if (!final && rate > 0.0 && done < total_)
    std::snprintf(eta, sizeof eta, ", ETA %.0f s", static_cast<double>(total_ - done) / rate);
  std::fprintf(stderr, "\r%s: %3.0f%% %.3g %s/s%s\033[K", label_.c_str(), pct, rate, unit_.c_str(), eta);
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressLine::finish() {
  if (!enabled_) return;
  std::lock_guard<std::mutex> lock(mutex_);
  if (!drawn_) return;
  draw(done_.load(), true);
  std::fprintf(stderr, " in %.1f s\n",
               std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count());
  drawn_ = false;
  enabled_ = false;
}

}  // namespace rfidray::cli
