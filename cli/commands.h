#pragma once
// Module cli — the rfidray command: main.cpp, this registry and one cmd_<name>.cpp per subcommand, nothing
// else. May include every module and adapter; nothing includes it.
//
// Registry of subcommands. Each cmd_<name>.cpp defines one setup function, listed in commands.cpp, which is also
// the one place that knows which adapters this build has (it registers their world loader and subcommands).
#include <CLI/CLI.hpp>
#include <functional>

#include "io/world_source.h"

namespace rfidray::cli {

// Adds every subcommand to `app` and registers the adapters' world loader with io (io/world_source.h).
void register_commands(CLI::App& app);
// Runs the callback of the subcommand that was parsed; returns the process exit code.
int run_selected(CLI::App& app);

// A subcommand: `setup` adds it (options bound to state it owns) and returns the runner.
using CommandSetup = std::function<std::function<int()>(CLI::App& app)>;

// Adds --channel (the channel level, as every command calls it) with --level, its former name in link and view,
// as an alias that --help names as such.
void add_channel_option_with_level_alias(CLI::App& cmd, std::string& level, const std::string& levels_help);

// Adds --world, --resource-path and --materials (a world file instead of a scenario) to a subcommand.
void add_world_options(CLI::App& cmd, io::WorldSourceOptions& options);

}  // namespace rfidray::cli
