#pragma once
// Runs the rfidray binary under test (RFIDRAY_BINARY) through the shell, for the CLI tests: stdout and stderr
// together, and the exit status (−1 when it did not exit normally, e.g. killed by a signal).
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace rfidray::testing {

struct CliResult {
  int status = -1;
  std::string output;  // stdout and stderr
};

// `prefix` runs in the same shell before the binary (ulimit, trap, cd …).
inline CliResult run_rfidray(const std::string& args, const std::string& prefix = "") {
  CliResult r;
  FILE* p = popen((prefix + RFIDRAY_BINARY + " " + args + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

}  // namespace rfidray::testing
