#pragma once
// Runs a shell command for a test: stdout and stderr together, and the exit status (−1 when it did not exit
// normally, e.g. killed by a signal). run_rfidray.h builds on it for the rfidray binary under test.
#include <sys/wait.h>

#include <cstdio>
#include <string>

namespace rfidray::testing {

struct CommandResult {
  int status = -1;
  std::string output;  // stdout and stderr
};

inline CommandResult run_command(const std::string& command) {
  CommandResult r;
  FILE* p = popen((command + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.output.append(buf, n);
  const int st = pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

}  // namespace rfidray::testing
