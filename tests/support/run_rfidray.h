#pragma once
// Runs the rfidray binary under test (RFIDRAY_BINARY) through the shell, for the CLI tests: stdout and stderr
// together, and the exit status (−1 when it did not exit normally, e.g. killed by a signal).
#include <string>

#include "tests/support/run_command.h"

namespace rfidray::testing {

using CliResult = CommandResult;

// `prefix` runs in the same shell before the binary (ulimit, trap, cd …).
inline CliResult run_rfidray(const std::string& args, const std::string& prefix = "") {
  return run_command(prefix + RFIDRAY_BINARY + " " + args);
}

}  // namespace rfidray::testing
