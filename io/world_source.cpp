#include "io/world_source.h"

#include <iostream>

#include "core/error.h"

namespace rfidray::io {
namespace {

WorldLoader& loader() {
  static WorldLoader l;
  return l;
}

}  // namespace

void register_world_loader(WorldLoader l) { loader() = std::move(l); }

bool world_import_available() { return static_cast<bool>(loader()); }

WorldSource load_world_source(const WorldSourceOptions& options, const std::string& default_material) {
  if (!loader())
    throw InputError(options.file + ": rfidray was built without sdformat 12, so it cannot read SDF worlds "
                     "(install libsdformat-dev and libassimp-dev, e.g. bash .ci/install-deps --gazebo, and rebuild)");
  return loader()(options, default_material);
}

void print_world_remarks(const WorldSource& world) {
  for (const auto& w : world.warnings) std::cerr << "rfidray: warning: " << w << "\n";
  for (const auto& n : world.notes) std::cerr << "rfidray: note: " << n << "\n";
}

}  // namespace rfidray::io
