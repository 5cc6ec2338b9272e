#pragma once
// Radio materials of a Gazebo world, from a mapping file (YAML), since SDF has no radio materials:
//
//   default_material: concrete          # every surface no rule names ("" or absent: such a surface is an error)
//   materials:                          # user materials, as a scenario's scene.materials
//     - {name: drywall, relative_permittivity: 2.7, conductivity_s_m: 0.02, thickness_m: 0.0125}
//   models: {crate: wood, rack_row: metal}    # model name, scoped ("rack_row::rack1") or plain; nearest model wins
//   links: {"rack_row::base": metal}           # scoped link name
//   collisions: {"barrel::link::ball": glass}  # scoped collision name
//   meshes: {beam.dae: metal}                  # mesh file name, or the URI as written
//   mesh_materials: {steel: metal}             # material names inside mesh files (COLLADA <material name>)
//
// For one surface the most specific rule wins: collision, link, nearest model (then its parents), mesh file,
// mesh material name, then a mesh material name that is itself a radio material, then default_material.
#include <map>
#include <string>
#include <vector>

#include "core/material.h"

namespace rfidray::gazebo {

struct MaterialRules {
  std::string source;  // the mapping file ("" when none)
  std::string default_material;
  std::vector<RadioMaterial> user_materials;
  std::map<std::string, std::string> models, links, collisions, meshes, mesh_materials;
};

// Throws InputError "FILE:LINE: ..." for a malformed file, unknown keys or unknown material names.
MaterialRules load_material_rules(const std::string& path);

// Checks every material a rule names (user or built-in); `where` prefixes the message.
void check_material_rules(const MaterialRules& rules);

}  // namespace rfidray::gazebo
