#include "adapters/gazebo/plugin.h"

extern "C" const rfidray::gazebo::AdaptersPlugin* rfidray_adapters_plugin() {
  using namespace rfidray::gazebo;
#ifdef RFIDRAY_HAVE_IGN_TRANSPORT
  static const AdaptersPlugin plugin{kAdaptersPluginAbi, &load_world_source, &run_bridge, &run_ros_bridge,
                                     &ros_private_params};
#else  // SDF import only: no live bridge in this build
  static const AdaptersPlugin plugin{kAdaptersPluginAbi, &load_world_source, nullptr, nullptr, nullptr};
#endif
  return &plugin;
}
