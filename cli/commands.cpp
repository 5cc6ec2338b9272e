#include "cli/commands.h"

#include <map>

namespace rfidray::cli {

// Each subcommand file provides one setup function (declared here, defined in cli/cmd_<name>.cpp).
// std::function<int()> setup_<name>(CLI::App& app);   (add one line per command)
std::function<int()> setup_simulate(CLI::App& app);
std::function<int()> setup_link(CLI::App& app);
std::function<int()> setup_gen_warehouse(CLI::App& app);
std::function<int()> setup_compare(CLI::App& app);
std::function<int()> setup_localize(CLI::App& app);
std::function<int()> setup_bench(CLI::App& app);
std::function<int()> setup_gazebo(CLI::App& app);

namespace {
std::map<const CLI::App*, std::function<int()>>& runners() {
  static std::map<const CLI::App*, std::function<int()>> r;
  return r;
}
void add(CLI::App& app, const CommandSetup& setup) {
  const size_t before = app.get_subcommands({}).size();
  auto runner = setup(app);
  auto subs = app.get_subcommands({});
  if (subs.size() > before) runners()[subs.back()] = std::move(runner);
}
}  // namespace

void register_commands(CLI::App& app) {
  add(app, setup_simulate);
  add(app, setup_link);
  add(app, setup_gen_warehouse);
  add(app, setup_compare);
  add(app, setup_localize);
  add(app, setup_bench);
  add(app, setup_gazebo);
}

int run_selected(CLI::App& app) {
  for (const CLI::App* sub : app.get_subcommands()) {
    auto it = runners().find(sub);
    if (it != runners().end()) return it->second();
  }
  return 1;
}

}  // namespace rfidray::cli
