#pragma once
// From the names a mesh carries (`usemtl`) to radio materials (core/material.h).
// Resolution order for one triangle of mesh M with usemtl name U:
//   1. by_mesh[M]            (scenario override for a whole mesh / object)
//   2. by_material[U]        (scenario override for a usemtl name)
//   3. U itself, if it names a user material or a built-in P.2040 material (case-insensitive)
//   4. default_material, if set (reported in `notes`)
//   5. otherwise InputError naming the mesh and the name.
#include <map>
#include <string>
#include <vector>

#include "core/material.h"
#include "raytrace/triangle_mesh.h"

namespace rfidray {

struct MaterialAssignment {
  std::map<std::string, std::string> by_mesh;      // mesh/object name → radio material name
  std::map<std::string, std::string> by_material;  // usemtl name → radio material name
  std::vector<RadioMaterial> user_materials;       // take precedence over built-ins of the same name
  std::string default_material;                    // "" → an unknown name is an error
  std::string override_all;                        // non-empty: every surface gets this material
  double thickness_m = -1.0;                       // ≥ 0: replaces every resolved material's thickness
  bool solid = false;                              // true: every resolved material bounds solids (RadioMaterial::solid)
};

struct ResolvedMaterials {
  std::vector<RadioMaterial> materials;             // distinct materials used
  std::vector<std::vector<uint32_t>> per_triangle;  // [mesh][triangle] → index into materials
  std::vector<std::string> notes;                   // defaults applied, overrides used (for the user)
};

// Looks a radio material up by name: user materials first, then P.2040 built-ins. Throws InputError
// listing the known names when `name` is neither; `context` says where the name came from.
RadioMaterial find_radio_material(const std::string& name, const std::vector<RadioMaterial>& user,
                                  const std::string& context);

ResolvedMaterials resolve_materials(const std::vector<TriangleMesh>& meshes, const MaterialAssignment& assignment);

}  // namespace rfidray
