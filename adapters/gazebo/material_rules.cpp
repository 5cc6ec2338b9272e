#include "adapters/gazebo/material_rules.h"

#include <yaml-cpp/yaml.h>

#include <map>

#include "core/error.h"
#include "io/checked_yaml.h"
#include "raytrace/material_map.h"
#include "core/number_text.h"

namespace rfidray::gazebo {
namespace {

// {name: radio material}
std::map<std::string, std::string> names(const io::YamlFile& f, const YAML::Node& n, const std::string& field) {
  if (!n.IsMap()) throw f.error(n, field, "must be a map {name: radio material}");
  std::map<std::string, std::string> out;
  for (auto it = n.begin(); it != n.end(); ++it) {
    const std::string k = f.scalar(it->first, field);
    out[k] = f.scalar(it->second, field + "." + k);
  }
  return out;
}

}  // namespace

MaterialRules load_material_rules(const std::string& path) {
  const io::YamlFile f(path);
  const YAML::Node root = io::load_yaml_file(path, "material map");
  MaterialRules r;
  r.source = path;
  if (!root.IsDefined() || root.IsNull()) return r;
  io::YamlMap top(f, root, "");
  if (auto v = top.get("default_material")) r.default_material = f.scalar(*v, "default_material");
  if (auto v = top.get("materials")) {
    if (!v->IsSequence()) throw f.error(*v, "materials", "must be a list of {name, relative_permittivity, conductivity_s_m, thickness_m, solid}");
    for (size_t i = 0; i < v->size(); ++i) {
      io::YamlMap m(f, (*v)[i], "materials[" + std::to_string(i) + "]");
      const std::string name = f.scalar(m.required("name"), m.field("name"));
      const YAML::Node eps_node = m.required("relative_permittivity");
      const double eps = f.number(eps_node, m.field("relative_permittivity"));
      if (!(eps > 0.0)) throw f.error(eps_node, m.field("relative_permittivity"), "must be > 0 (got " + num(eps) + ")");
      const double sigma = m.non_negative({"conductivity_s_m"}, 0.0);
      const double thickness = m.non_negative({"thickness_m"}, 0.0);
      // Gazebo's <box> and <cylinder> collisions are closed solids: `solid: true` makes a wall's box one slab
      // (RadioMaterial::solid) instead of two.
      bool solid = false;
      if (auto s = m.get("solid")) solid = f.boolean(*s, m.field("solid"));
      m.finish();
      r.user_materials.push_back(user_material(name, eps, sigma, thickness));
      r.user_materials.back().solid = solid;
    }
  }
  if (auto v = top.get("models")) r.models = names(f, *v, "models");
  if (auto v = top.get("links")) r.links = names(f, *v, "links");
  if (auto v = top.get("collisions")) r.collisions = names(f, *v, "collisions");
  if (auto v = top.get("meshes")) r.meshes = names(f, *v, "meshes");
  if (auto v = top.get("mesh_materials")) r.mesh_materials = names(f, *v, "mesh_materials");
  top.finish();
  check_material_rules(r);
  return r;
}

void check_material_rules(const MaterialRules& r) {
  const std::string where = r.source.empty() ? std::string("material map") : r.source;
  if (!r.default_material.empty()) find_radio_material(r.default_material, r.user_materials, where + ": default_material");
  for (const auto* group : {&r.models, &r.links, &r.collisions, &r.meshes, &r.mesh_materials})
    for (const auto& [from, to] : *group) find_radio_material(to, r.user_materials, where + ": '" + from + "'");
}

}  // namespace rfidray::gazebo
