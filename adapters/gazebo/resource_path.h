#pragma once
// Where Gazebo finds model:// resources, and URI resolution for <include> and <mesh><uri>.
#include <filesystem>
#include <string>
#include <vector>

namespace rfidray::gazebo {

// The directories searched for model://NAME/...: `extra` first (the --resource-path flag, each entry may hold
// several directories separated by ':'), then IGN_GAZEBO_RESOURCE_PATH, GZ_SIM_RESOURCE_PATH and SDF_PATH, as
// Gazebo Fortress and sdformat read them. Directories that do not exist are left out.
std::vector<std::filesystem::path> resource_dirs(const std::vector<std::string>& extra);

// A file named by an SDF URI: model://NAME/REST and package://NAME/REST (in the first resource directory
// holding NAME/REST), file:///ABS, an absolute path, or a path relative to `base_dir` (the SDF file's
// directory). Throws InputError naming the URI and the directories searched; web URIs (Fuel) are refused
// with what to do instead.
std::filesystem::path resolve_uri(const std::string& uri, const std::filesystem::path& base_dir,
                                  const std::vector<std::filesystem::path>& dirs);

}  // namespace rfidray::gazebo
