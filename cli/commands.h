#pragma once
// Registry of subcommands. Each cmd_*.cpp defines one `Command` and adds it in commands.cpp.
#include <CLI/CLI.hpp>
#include <functional>

namespace rfidray::cli {

void register_commands(CLI::App& app);
// Runs the callback of the subcommand that was parsed; returns the process exit code.
int run_selected(CLI::App& app);

// A subcommand: `setup` adds it (options bound to state it owns) and returns the runner.
using CommandSetup = std::function<std::function<int()>(CLI::App& app)>;

}  // namespace rfidray::cli
