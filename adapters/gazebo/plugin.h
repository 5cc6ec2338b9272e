#pragma once
// The Gazebo/ROS adapters as a plugin of the rfidray program: librfidray_adapters.so, beside the binary, holds
// this folder's code and adapters/ros (sdformat 12, ign-transport 11, ign-msgs 8, protobuf, roscpp) and is
// loaded on first use — an SDF world (--world, a .world/.sdf scene) or `rfidray gazebo` — so that every other
// run does not load those libraries. Their static initialisers were most of the program's start-up: `rfidray
// --help` 0.095 → 0.025 s in a release build, 0.57–0.61 → 0.15 s under the sanitizers
// (bench/results/setup/README.md).
//
// The plugin links none of rfidray's own libraries: it uses the program's (the binary exports its symbols), so
// there is one memory budget, one world-loader registry, one of everything. It is therefore built for one
// binary: kAdaptersPluginAbi is checked at load, and the plugin is found only beside the binary it was built
// with (cli/adapters_plugin.h). The test executables and the Python module link rfidray_gazebo statically and
// do not use this.
#include <string>
#include <vector>

#include "adapters/gazebo/bridge.h"
#include "adapters/gazebo/gazebo_world.h"
#include "adapters/gazebo/ros_bridge.h"

namespace rfidray::gazebo {

// Bumped when AdaptersPlugin or the option structs it passes change shape.
inline constexpr int kAdaptersPluginAbi = 1;

// The plugin's entry points; each is the function of the same name in this folder.
struct AdaptersPlugin {
  int abi = kAdaptersPluginAbi;
  io::WorldSource (*load_world_source)(const io::WorldSourceOptions& options, const std::string& default_material);
  int (*run_bridge)(const BridgeOptions& options);
  int (*run_ros_bridge)(const RosBridgeOptions& options);
  RosParams (*ros_private_params)(const std::string& node_name, const std::vector<std::string>& ros_args);
};

}  // namespace rfidray::gazebo

// The one symbol the program looks up (dlsym) in the plugin.
extern "C" const rfidray::gazebo::AdaptersPlugin* rfidray_adapters_plugin();
