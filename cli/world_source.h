#pragma once
// Gazebo SDF worlds as a source of scenarios for `simulate --world` and `link --world`: the hook between the
// subcommands and the importer (cli/gazebo/), which is only built when sdformat 12 is found. Without it the
// options exist and say so.
#include <CLI/CLI.hpp>
#include <memory>
#include <string>
#include <vector>

#include "core/channel.h"
#include "core/scenario.h"
#include "raytrace/scene.h"

namespace rfidray::cli {

struct WorldSourceOptions {
  std::string file;                        // --world
  std::vector<std::string> resource_path;  // --resource-path (before IGN_GAZEBO_RESOURCE_PATH, ...)
  std::string materials_file;              // --materials
};

// Adds --world, --resource-path and --materials to a subcommand.
void add_world_options(CLI::App& cmd, WorldSourceOptions& options);

struct WorldSource {
  Scenario scenario;                    // antennas and tags fixed where the world puts them
  std::shared_ptr<const Scene> scene;   // the world's collision surfaces with radio materials
  std::vector<std::string> warnings;    // sdformat's and the mesh loaders' complaints that did not stop the import
  std::vector<std::string> notes;       // defaults applied
  std::string summary;                  // one line: world name, models, links, triangles, antennas, tags
};

// True when rfidray was built with sdformat 12 (and assimp for DAE/STL meshes).
bool world_import_available();
// Throws InputError naming the file when the world cannot be used (or when built without sdformat).
// `default_material` ("" = the map's own, or 'concrete' without a map) applies to unmapped surfaces.
WorldSource load_world_source(const WorldSourceOptions& options, const std::string& default_material = "");

// Prints warnings and notes to stderr as `rfidray: warning: ...` / `rfidray: note: ...`.
void print_world_remarks(const WorldSource& world);

}  // namespace rfidray::cli
