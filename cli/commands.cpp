#include "cli/commands.h"

#include <map>

#include "core/error.h"

#ifdef RFIDRAY_HAVE_SDFORMAT
#include "cli/adapters_plugin.h"
#endif

namespace rfidray::cli {

// Each subcommand file provides one setup function (declared here, defined in cli/cmd_<name>.cpp).
std::function<int()> setup_simulate(CLI::App& app);
std::function<int()> setup_link(CLI::App& app);
std::function<int()> setup_gen_warehouse(CLI::App& app);
std::function<int()> setup_compare(CLI::App& app);
std::function<int()> setup_localize(CLI::App& app);
std::function<int()> setup_calibrate(CLI::App& app);
std::function<int()> setup_bench(CLI::App& app);
std::function<int()> setup_import(CLI::App& app);
std::function<int()> setup_coverage(CLI::App& app);
std::function<int()> setup_place(CLI::App& app);
std::function<int()> setup_view(CLI::App& app);
#ifdef RFIDRAY_HAVE_IGN_TRANSPORT
std::function<int()> setup_gazebo(CLI::App& app);
#endif

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

#ifndef RFIDRAY_HAVE_IGN_TRANSPORT
// Without the bridge the subcommand still exists and says what is missing.
std::function<int()> setup_gazebo(CLI::App& app) {
  CLI::App* cmd = app.add_subcommand("gazebo", "Live bridge to a running Gazebo (not in this build)");
  cmd->allow_extras();
  return [] () -> int {
    throw InputError("rfidray was built without ign-transport 11 / ign-msgs 8 (and sdformat 12), so it has no live "
                     "Gazebo bridge: install them (bash .ci/install-deps --gazebo) and rebuild");
  };
}
#endif
}  // namespace

void register_commands(CLI::App& app) {
#ifdef RFIDRAY_HAVE_SDFORMAT
  // SDF worlds load through the adapters plugin, loaded here on first use (cli/adapters_plugin.h).
  io::register_world_loader([](const io::WorldSourceOptions& options, const std::string& default_material) {
    return adapters_plugin().load_world_source(options, default_material);
  });
#endif
  add(app, setup_simulate);
  add(app, setup_link);
  add(app, setup_gen_warehouse);
  add(app, setup_compare);
  add(app, setup_localize);
  add(app, setup_calibrate);
  add(app, setup_bench);
  add(app, setup_import);
  add(app, setup_coverage);
  add(app, setup_place);
  add(app, setup_view);
  add(app, setup_gazebo);
}

int run_selected(CLI::App& app) {
  for (const CLI::App* sub : app.get_subcommands()) {
    auto it = runners().find(sub);
    if (it != runners().end()) return it->second();
  }
  return 1;
}

void add_channel_option_with_level_alias(CLI::App& cmd, std::string& level, const std::string& levels_help) {
  cmd.add_option("--channel,--level", level, levels_help + " (--level is an alias of --channel)");
}

void add_world_options(CLI::App& cmd, io::WorldSourceOptions& o) {
  cmd.add_option("--world", o.file, "Gazebo SDF world (.world/.sdf): collisions, RFID antennas and tags (see README)");
  cmd.add_option("--resource-path", o.resource_path,
                 "Directory holding model://NAME folders, searched before IGN_GAZEBO_RESOURCE_PATH, "
                 "GZ_SIM_RESOURCE_PATH and SDF_PATH (repeatable; ':' separates several)");
  cmd.add_option("--materials", o.materials_file,
                 "Material map of the world (YAML: default_material, materials, models, links, collisions, meshes, "
                 "mesh_materials)");
}

}  // namespace rfidray::cli
