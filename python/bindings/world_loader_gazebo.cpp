// Built with the Gazebo adapter: Scene.load reads SDF worlds as `rfidray link --world` does.
#include "adapters/gazebo/gazebo_world.h"
#include "io/world_source.h"
#include "python/bindings/bindings.h"

namespace rfidray::py {

void register_world_loader() { io::register_world_loader(&gazebo::load_world_source); }

}  // namespace rfidray::py
