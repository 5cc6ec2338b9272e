// rfidray: one subcommand per use. Each subcommand lives in its own cli/cmd_*.cpp and registers itself here.
#include <CLI/CLI.hpp>
#include <iostream>
#include <new>

#include "cli/commands.h"
#include "core/error.h"
#include "core/memory_budget.h"

int main(int argc, char** argv) {
  CLI::App app{"rfidray — ray-traced multipath channel engine for passive UHF RFID"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "rfidray 0.1.0");
  std::string max_memory;
  app.add_option("--max-memory", max_memory,
                 "Memory budget for the size checks made before large allocations (scenes, grids, generated "
                 "warehouses): 512M, 4G, ... (default: this machine's physical memory)");
  app.fallthrough();  // --max-memory may also follow the subcommand
  rfidray::cli::register_commands(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0 through CLI11; every other parse error is bad input: exit 2, naming the flag
    // (CLI11's messages do: "--rows: ...", "Could not convert: --rows = ...").
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success)) return app.exit(e);
    std::cerr << "rfidray: error: " << rfidray::clip(e.what(), 300) << "\nRun with --help for more information.\n";
    return 2;
  }
  try {
    if (!max_memory.empty())
      rfidray::set_memory_budget_bytes(rfidray::parse_memory_size(max_memory, "--max-memory"), "--max-memory");
    return rfidray::cli::run_selected(app);
  } catch (const rfidray::InputError& e) {
    std::cerr << "rfidray: error: " << e.what() << "\n";
    return 2;
  } catch (const std::bad_alloc&) {
    // Sizes that come from input are checked where they enter; this is what remains (the machine's memory).
    std::cerr << "rfidray: error: out of memory (the input's size is within rfidray's limits but not this "
                 "machine's; see README, \"Limits and errors\")\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << "rfidray: error: " << e.what() << "\n";
    return 1;
  }
}
