#pragma once
// World files (Gazebo SDF) as a source of scenarios for `simulate --world` and `link --world`. io knows no
// world format: an adapter (adapters/gazebo) registers its loader once at start-up (cli/commands.cpp), and
// without one load_world_source says what to install. Not thread-safe to register while loading.
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/scenario.h"
#include "raytrace/scene.h"

namespace rfidray::io {

struct WorldSourceOptions {
  std::string file;                        // --world
  std::vector<std::string> resource_path;  // --resource-path (before IGN_GAZEBO_RESOURCE_PATH, ...)
  std::string materials_file;              // --materials
};

struct WorldSource {
  Scenario scenario;                    // antennas and tags fixed where the world puts them
  std::shared_ptr<const Scene> scene;   // the world's collision surfaces with radio materials
  std::vector<std::string> warnings;    // the importer's complaints that did not stop the import
  std::vector<std::string> notes;       // defaults applied
  std::string summary;                  // one line: world name, models, links, triangles, antennas, tags
};

// `default_material` ("" = the map's own, or 'concrete' without a map) applies to unmapped surfaces.
using WorldLoader = std::function<WorldSource(const WorldSourceOptions& options, const std::string& default_material)>;

// Installs the loader of world files (the last one registered wins).
void register_world_loader(WorldLoader loader);
// True when a loader is registered (rfidray was built with a world importer).
bool world_import_available();
// Throws InputError naming the file when the world cannot be used, or when no loader is registered.
WorldSource load_world_source(const WorldSourceOptions& options, const std::string& default_material = "");

// Prints warnings and notes to stderr as `rfidray: warning: ...` / `rfidray: note: ...`.
void print_world_remarks(const WorldSource& world);

}  // namespace rfidray::io
