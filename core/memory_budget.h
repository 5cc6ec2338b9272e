#pragma once
// The memory budget that size checks compare their estimates with before allocating (README, "Limits and
// errors"): by default the machine's physical memory, or what `rfidray --max-memory SIZE` set. The fixed
// ranges of core/limits.h still apply on top. Set once at start-up (not thread-safe to set while others read);
// reads are safe from any thread.
#include <string>

namespace rfidray {

// Bytes a run may use; the machine's physical memory (sysconf) until set_memory_budget_bytes.
double memory_budget_bytes();
// Where the budget came from, for messages: "this machine's memory" or "--max-memory".
const std::string& memory_budget_source();
void set_memory_budget_bytes(double bytes, const std::string& source);

// Throws InputError "WHAT would need about N GB (DETAIL), more than the memory budget of M GB (SOURCE)" when
// estimate_bytes exceeds the budget. `what` names the input ("scene: 3e8 triangles", "field 'duration_s'").
void check_memory_estimate(double estimate_bytes, const std::string& what, const std::string& detail);

// "4G", "512M", "1.5GiB", "2e9" (bytes; K/M/G/T are powers of 1024, with or without "iB"/"B"). Throws InputError
// "option OPTION: ..." for anything else or a size below 1 MiB.
double parse_memory_size(const std::string& text, const std::string& option);

}  // namespace rfidray
