#pragma once
// Mesh files as SDF <mesh><uri> names them, to one TriangleMesh in metres, Z up:
//  - .obj through load_obj (tinyobjloader, validated line by line);
//  - COLLADA (.dae), STL and the other formats assimp reads, through assimp, with every node transform applied.
// COLLADA keeps its own <unit> and <up_axis>: assimp scales the file to metres and turns it to Y up, and we turn
// Y up back to the Z up of SDF worlds, so a Z-up file in centimetres lands unrotated and 100 times smaller, and
// a Y-up file is stood up. STL and the rest carry no units: metres, as SDF says, axes as they are.
// Per-triangle material names are the file's own material names ("" for none, or for assimp's default).
#include <filesystem>
#include <string>
#include <vector>

#include "raytrace/assimp_mesh.h"  // mesh_formats_available()
#include "raytrace/triangle_mesh.h"

namespace rfidray {

// Throws InputError ("file: what") for a missing, unreadable or malformed file, or one without triangles.
// Remarks (points and lines skipped, ...) are appended to `warnings` when given.
TriangleMesh load_mesh_file(const std::filesystem::path& path, std::vector<std::string>* warnings = nullptr);

}  // namespace rfidray
