#pragma once
// Wavefront OBJ → triangle meshes (tinyobjloader). One TriangleMesh per object/group name (`o`/`g`),
// so a scenario can override materials per mesh; per-triangle material names are the `usemtl` names
// (radio material names, mapped later by raytrace/material_map.h). Polygons are fan-triangulated
// (convex planar polygons assumed).
//
// tinyobjloader is lenient (a bad number parses as 0, an out-of-range index is reported without its line),
// so a validation pass runs first and rejects malformed `v`/`f`/`usemtl` lines with file:line. tinyobjloader's
// own warnings (missing .mtl, unknown material in .mtl, ...) are returned as text, one per line.
#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include "raytrace/triangle_mesh.h"

namespace rfidray {

struct ObjScene {
  std::vector<TriangleMesh> meshes;
  std::vector<std::string> warnings;  // "file: message", for the caller to print
};

// Throws InputError ("file:line: what") for unreadable or malformed files.
ObjScene load_obj(const std::filesystem::path& path);

// Writes meshes as OBJ (one `o` per mesh, `usemtl` per material run) plus a .mtl beside it listing the
// material names (diffuse colours only, so viewers show something). Throws InputError if unwritable.
void write_obj(const std::filesystem::path& path, const std::vector<TriangleMesh>& meshes);
// The same into streams (`mtl_name` is the .mtl file name the OBJ's mtllib line gives), for writers that
// place the files themselves (gen-warehouse writes both atomically, io/atomic_file.h). A non-finite vertex is
// an internal error (std::logic_error naming the mesh), never written.
void write_obj(std::ostream& obj, std::ostream& mtl, const std::string& mtl_name, const std::vector<TriangleMesh>& meshes);

}  // namespace rfidray
