#pragma once
// Mesh formats other than OBJ (COLLADA, STL, ...) through assimp, the one place rfidray calls it. Built from
// assimp_mesh.cpp when CMake finds assimp, else from assimp_mesh_absent.cpp, whose loader says what is missing.
// Contract as load_mesh_file (raytrace/mesh_file.h): metres, Z up, throws InputError naming the file.
#include <filesystem>
#include <string>
#include <vector>

#include "raytrace/triangle_mesh.h"

namespace rfidray {

// True when this build reads mesh formats through assimp.
bool mesh_formats_available();

// `extension` is the file's lower-case extension (".dae" turns Y up to Z up).
TriangleMesh load_assimp_mesh(const std::filesystem::path& path, const std::string& extension,
                              std::vector<std::string>* warnings);

}  // namespace rfidray
