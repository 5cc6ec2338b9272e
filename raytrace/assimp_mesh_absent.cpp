// Built instead of assimp_mesh.cpp when CMake does not find assimp: only OBJ meshes load.
#include "core/error.h"
#include "raytrace/assimp_mesh.h"

namespace rfidray {

bool mesh_formats_available() { return false; }

TriangleMesh load_assimp_mesh(const std::filesystem::path& path, const std::string& ext, std::vector<std::string>*) {
  throw InputError(path.string() + ": '" + ext + "' meshes need assimp (rfidray was built without it; install "
                   "libassimp-dev and rebuild, or convert the mesh to OBJ)");
}

}  // namespace rfidray
