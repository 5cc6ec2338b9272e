// Built without the Gazebo adapter: world files stay unavailable and io::load_world_source says what to install.
#include "python/bindings/bindings.h"

namespace rfidray::py {

void register_world_loader() {}

}  // namespace rfidray::py
