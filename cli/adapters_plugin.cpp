#include "cli/adapters_plugin.h"

#include <dlfcn.h>

#include <filesystem>
#include <mutex>

#include "core/error.h"

namespace rfidray::cli {

std::string adapters_plugin_path() {
  std::error_code ec;
  const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw InputError("cannot find the rfidray binary's directory (/proc/self/exe: " + ec.message() + ")");
  return (exe.parent_path() / "librfidray_adapters.so").string();
}

const gazebo::AdaptersPlugin& adapters_plugin() {
  static std::once_flag once;
  static const gazebo::AdaptersPlugin* plugin = nullptr;
  static std::string error;
  std::call_once(once, [] {
    const std::string path = adapters_plugin_path();
    // RTLD_NOW: a symbol the plugin needs and the binary lacks is an error here, naming it, not a crash later.
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* why = dlerror();
      // dlerror() names the file and what is wrong (absent, a library it needs, a symbol the binary lacks).
      error = std::string("rfidray's Gazebo/ROS adapters could not be loaded (they are built beside the binary, as "
                          "librfidray_adapters.so; keep the two together): ") + (why ? why : path);
      return;
    }
    using Entry = const gazebo::AdaptersPlugin* (*)();
    auto entry = reinterpret_cast<Entry>(dlsym(handle, "rfidray_adapters_plugin"));
    if (!entry) {
      error = path + " is not rfidray's adapters plugin (no rfidray_adapters_plugin)";
      return;
    }
    const gazebo::AdaptersPlugin* p = entry();
    if (!p || p->abi != gazebo::kAdaptersPluginAbi) {
      error = path + " was built for another rfidray binary (plugin interface " +
              std::to_string(p ? p->abi : -1) + ", this binary " + std::to_string(gazebo::kAdaptersPluginAbi) +
              "): rebuild both";
      return;
    }
    plugin = p;  // never unloaded: its code runs until exit
  });
  if (!plugin) throw InputError(error);
  return *plugin;
}

}  // namespace rfidray::cli
