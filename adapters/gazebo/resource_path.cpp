#include "adapters/gazebo/resource_path.h"

#include <cstdlib>
#include <sstream>

#include "core/error.h"

namespace rfidray::gazebo {
namespace {

void add_list(const std::string& list, std::vector<std::filesystem::path>& out) {
  std::stringstream in(list);
  std::string dir;
  while (std::getline(in, dir, ':')) {
    if (dir.empty()) continue;
    std::error_code ec;
    if (!std::filesystem::is_directory(dir, ec)) continue;
    const std::filesystem::path p = std::filesystem::path(dir).lexically_normal();
    bool seen = false;
    for (const auto& q : out) seen = seen || q == p;
    if (!seen) out.push_back(p);
  }
}

bool starts_with(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

}  // namespace

std::vector<std::filesystem::path> resource_dirs(const std::vector<std::string>& extra) {
  std::vector<std::filesystem::path> out;
  for (const std::string& e : extra) add_list(e, out);
  for (const char* var : {"IGN_GAZEBO_RESOURCE_PATH", "GZ_SIM_RESOURCE_PATH", "SDF_PATH"})
    if (const char* v = std::getenv(var)) add_list(v, out);
  return out;
}

std::filesystem::path resolve_uri(const std::string& uri, const std::filesystem::path& base_dir,
                                  const std::vector<std::filesystem::path>& dirs) {
  if (uri.empty()) throw InputError("empty URI");
  if (starts_with(uri, "http://") || starts_with(uri, "https://"))
    throw InputError("URI '" + uri + "' is on the web (Gazebo Fuel): download the model and add its folder to "
                     "--resource-path or IGN_GAZEBO_RESOURCE_PATH, then name it model://NAME");
  for (const char* scheme : {"model://", "package://"}) {
    if (!starts_with(uri, scheme)) continue;
    const std::string rest = uri.substr(std::string(scheme).size());
    std::string searched;
    for (const auto& d : dirs) {
      const std::filesystem::path p = d / rest;
      if (std::filesystem::exists(p)) return p.lexically_normal();
      searched += (searched.empty() ? "" : ", ") + d.string();
    }
    throw InputError("cannot find '" + uri + "' in the resource path (" +
                     (searched.empty() ? std::string("empty") : searched) +
                     "); add the folder holding '" + rest.substr(0, rest.find('/')) +
                     "' with --resource-path DIR or IGN_GAZEBO_RESOURCE_PATH");
  }
  std::string path = uri;
  if (starts_with(uri, "file://")) path = uri.substr(7);
  else if (uri.find("://") != std::string::npos) throw InputError("unsupported URI scheme in '" + uri + "' (model://, package://, file:// or a path)");
  std::filesystem::path p(path);
  if (p.is_relative()) p = base_dir / p;
  p = p.lexically_normal();
  if (!std::filesystem::exists(p)) throw InputError("no such file '" + p.string() + "' (URI '" + uri + "')");
  return p;
}

}  // namespace rfidray::gazebo
