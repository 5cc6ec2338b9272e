#include "cli/world_source.h"

#include <iostream>

#include "core/error.h"
#include "raytrace/raytraced_channel.h"

#ifdef RFIDRAY_HAVE_SDFORMAT
#include "cli/gazebo/gazebo_world.h"
#endif

namespace rfidray::cli {

void add_world_options(CLI::App& cmd, WorldSourceOptions& o) {
  cmd.add_option("--world", o.file, "Gazebo SDF world (.world/.sdf): collisions, RFID antennas and tags (see README)");
  cmd.add_option("--resource-path", o.resource_path,
                 "Directory holding model://NAME folders, searched before IGN_GAZEBO_RESOURCE_PATH, "
                 "GZ_SIM_RESOURCE_PATH and SDF_PATH (repeatable; ':' separates several)");
  cmd.add_option("--materials", o.materials_file,
                 "Material map of the world (YAML: default_material, materials, models, links, collisions, meshes, "
                 "mesh_materials)");
}

bool world_import_available() {
#ifdef RFIDRAY_HAVE_SDFORMAT
  return true;
#else
  return false;
#endif
}

WorldSource load_world_source(const WorldSourceOptions& options, const std::string& default_material) {
#ifdef RFIDRAY_HAVE_SDFORMAT
  gazebo::WorldOptions wo;
  wo.file = options.file;
  wo.resource_path = options.resource_path;
  wo.materials_file = options.materials_file;
  wo.default_material = default_material;
  gazebo::GazeboWorld world = gazebo::load_world(wo);
  WorldSource out;
  out.scene = gazebo::build_scene(world);
  out.scenario = world.scenario;
  out.warnings = world.warnings;
  out.notes = world.notes;
  for (const std::string& n : out.scene->notes()) out.notes.push_back(world.file + ": " + n);
  size_t models = 0, links = 0;
  for (const auto& e : world.entities) (e.kind == gazebo::Entity::Kind::kModel ? models : links)++;
  out.summary = "world '" + world.name + "' (" + world.file + "): " + std::to_string(models) + " models, " +
                std::to_string(links) + " links, " + std::to_string(world.collisions.size()) + " collisions, " +
                std::to_string(world.triangle_count()) + " triangles, " + std::to_string(world.scenario.antennas.size()) +
                " antennas, " + std::to_string(world.scenario.tags.size()) + " tags";
  return out;
#else
  throw InputError(options.file + ": rfidray was built without sdformat 12, so it cannot read SDF worlds "
                   "(install libsdformat-dev and libassimp-dev, e.g. bash .ci/install-deps --gazebo, and rebuild)");
#endif
}

void print_world_remarks(const WorldSource& world) {
  for (const auto& w : world.warnings) std::cerr << "rfidray: warning: " << w << "\n";
  for (const auto& n : world.notes) std::cerr << "rfidray: note: " << n << "\n";
}

}  // namespace rfidray::cli
