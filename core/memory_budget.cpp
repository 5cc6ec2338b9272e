#include "core/memory_budget.h"

#include <unistd.h>

#include <atomic>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "core/error.h"
#include "core/number_text.h"

namespace rfidray {
namespace {

double physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGE_SIZE);
  // Unknown (a sandbox that hides it): no budget beyond core/limits.h's fixed ranges.
  return pages > 0 && page > 0 ? double(pages) * double(page) : INFINITY;
}

std::atomic<double> g_budget{-1.0};
std::string g_source = "this machine's memory";

std::string gb(double bytes) { return rounded_text(bytes / 1e9, 3) + " GB"; }

}  // namespace

double memory_budget_bytes() {
  double b = g_budget.load();
  if (b < 0.0) {
    b = physical_memory_bytes();
    g_budget.store(b);
  }
  return b;
}

const std::string& memory_budget_source() { return g_source; }

void set_memory_budget_bytes(double bytes, const std::string& source) {
  g_source = source;
  g_budget.store(bytes);
}

void check_memory_estimate(double estimate_bytes, const std::string& what, const std::string& detail) {
  const double budget = memory_budget_bytes();
  if (estimate_bytes > budget)
    throw InputError(what + " would need about " + gb(estimate_bytes) + " (" + detail + "), more than the memory budget of " +
                     gb(budget) + " (" + memory_budget_source() + "; rfidray --max-memory SIZE sets it)");
}

double parse_memory_size(const std::string& text, const std::string& option) {
  size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  std::string unit = used ? text.substr(used) : std::string();
  for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  double scale = 0.0;
  if (unit.empty() || unit == "B") scale = 1.0;
  else if (unit == "K" || unit == "KB" || unit == "KIB") scale = 1024.0;
  else if (unit == "M" || unit == "MB" || unit == "MIB") scale = 1024.0 * 1024.0;
  else if (unit == "G" || unit == "GB" || unit == "GIB") scale = 1024.0 * 1024.0 * 1024.0;
  else if (unit == "T" || unit == "TB" || unit == "TIB") scale = 1024.0 * 1024.0 * 1024.0 * 1024.0;
  const double bytes = value * scale;
  if (used == 0 || scale == 0.0 || !std::isfinite(bytes) || bytes < 1024.0 * 1024.0)
    throw InputError("option " + option + ": '" + clip(text) + "' is not a memory size of at least 1M (e.g. 512M, 4G)");
  return bytes;
}

}  // namespace rfidray
