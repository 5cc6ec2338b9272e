#include "raytrace/mesh_file.h"

#include <algorithm>
#include <cctype>

#include "core/error.h"
#include "raytrace/assimp_mesh.h"
#include "raytrace/obj_loader.h"

namespace rfidray {
namespace {

std::string lower_extension(const std::filesystem::path& p) {
  std::string e = p.extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return e;
}

TriangleMesh load_obj_file(const std::filesystem::path& path, std::vector<std::string>* warnings) {
  ObjScene obj = load_obj(path);
  if (warnings) warnings->insert(warnings->end(), obj.warnings.begin(), obj.warnings.end());
  TriangleMesh out;
  out.name = path.stem().string();
  for (const TriangleMesh& m : obj.meshes) out.append(m);
  return out;
}

}  // namespace

TriangleMesh load_mesh_file(const std::filesystem::path& path, std::vector<std::string>* warnings) {
  const std::string file = path.string();
  if (!std::filesystem::is_regular_file(path))
    throw InputError(file + ": no such mesh file");
  const std::string ext = lower_extension(path);
  if (ext == ".obj") return load_obj_file(path, warnings);
  return load_assimp_mesh(path, ext, warnings);
}

}  // namespace rfidray
