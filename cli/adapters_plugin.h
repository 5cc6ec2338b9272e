#pragma once
// Loads the Gazebo/ROS adapters plugin (adapters/gazebo/plugin.h) on first use: librfidray_adapters.so in the
// directory of the running binary (/proc/self/exe, symbolic links resolved). Thread-safe (loaded once).
// Throws InputError when it is missing, cannot be loaded (the loader's message, e.g. a missing library) or was
// built for another binary.
#include <string>

#include "adapters/gazebo/plugin.h"

namespace rfidray::cli {

const gazebo::AdaptersPlugin& adapters_plugin();

// Where adapters_plugin() looks: <directory of this binary>/librfidray_adapters.so.
std::string adapters_plugin_path();

}  // namespace rfidray::cli
