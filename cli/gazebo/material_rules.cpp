#include "cli/gazebo/material_rules.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>

#include "core/error.h"
#include "raytrace/material_map.h"

namespace rfidray::cli::gazebo {
namespace {

struct File {
  std::string path;
  std::string at(const YAML::Node& n) const {
    return n.Mark().line < 0 ? path + ": " : path + ":" + std::to_string(n.Mark().line + 1) + ": ";
  }
  InputError error(const YAML::Node& n, const std::string& field, const std::string& what) const {
    return InputError(at(n) + "field '" + field + "': " + what);
  }
  std::string scalar(const YAML::Node& n, const std::string& field) const {
    if (!n.IsScalar()) throw error(n, field, "must be a single value");
    return n.Scalar();
  }
  double number(const YAML::Node& n, const std::string& field, double min, bool allow_min) const {
    const std::string s = scalar(n, field);
    double v = 0.0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      throw error(n, field, "must be a number (got '" + s + "')");
    }
    if (!std::isfinite(v) || v < min || (!allow_min && v == min))
      throw error(n, field, std::string("must be ") + (allow_min ? ">= " : "> ") + std::to_string(min) + " (got '" + s + "')");
    return v;
  }
  std::map<std::string, std::string> names(const YAML::Node& n, const std::string& field) const {
    if (!n.IsMap()) throw error(n, field, "must be a map {name: radio material}");
    std::map<std::string, std::string> out;
    for (auto it = n.begin(); it != n.end(); ++it) {
      const std::string k = scalar(it->first, field);
      out[k] = scalar(it->second, field + "." + k);
    }
    return out;
  }
};

}  // namespace

MaterialRules load_material_rules(const std::string& path) {
  File f{path};
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw InputError(path + ": cannot open material map (" +
                     std::string(std::filesystem::exists(path) ? "unreadable" : "no such file") + ")");
  } catch (const YAML::ParserException& e) {
    throw InputError(path + ":" + std::to_string(e.mark.line + 1) + ": malformed YAML: " + e.msg);
  }
  MaterialRules r;
  r.source = path;
  if (!root.IsDefined() || root.IsNull()) return r;
  if (!root.IsMap()) throw f.error(root, "(top level)", "must be a map (default_material, materials, models, ...)");
  for (auto it = root.begin(); it != root.end(); ++it) {
    const std::string key = f.scalar(it->first, "(top level)");
    const YAML::Node v = it->second;
    if (key == "default_material") {
      r.default_material = f.scalar(v, key);
    } else if (key == "materials") {
      if (!v.IsSequence()) throw f.error(v, key, "must be a list of {name, relative_permittivity, conductivity_s_m, thickness_m}");
      for (size_t i = 0; i < v.size(); ++i) {
        const std::string field = key + "[" + std::to_string(i) + "]";
        const YAML::Node m = v[i];
        if (!m.IsMap()) throw f.error(m, field, "must be a map");
        double eps = 0.0, sigma = 0.0, thick = 0.0;
        std::string name;
        bool has_eps = false;
        for (auto jt = m.begin(); jt != m.end(); ++jt) {
          const std::string k = f.scalar(jt->first, field);
          if (k == "name") name = f.scalar(jt->second, field + ".name");
          else if (k == "relative_permittivity") eps = f.number(jt->second, field + "." + k, 0.0, false), has_eps = true;
          else if (k == "conductivity_s_m") sigma = f.number(jt->second, field + "." + k, 0.0, true);
          else if (k == "thickness_m") thick = f.number(jt->second, field + "." + k, 0.0, true);
          else throw f.error(jt->first, field + "." + k, "unknown key (name, relative_permittivity, conductivity_s_m, thickness_m)");
        }
        if (name.empty()) throw f.error(m, field + ".name", "is required");
        if (!has_eps) throw f.error(m, field + ".relative_permittivity", "is required");
        r.user_materials.push_back(user_material(name, eps, sigma, thick));
      }
    } else if (key == "models") {
      r.models = f.names(v, key);
    } else if (key == "links") {
      r.links = f.names(v, key);
    } else if (key == "collisions") {
      r.collisions = f.names(v, key);
    } else if (key == "meshes") {
      r.meshes = f.names(v, key);
    } else if (key == "mesh_materials") {
      r.mesh_materials = f.names(v, key);
    } else {
      throw f.error(it->first, key,
                    "unknown key (default_material, materials, models, links, collisions, meshes, mesh_materials)");
    }
  }
  check_material_rules(r);
  return r;
}

void check_material_rules(const MaterialRules& r) {
  const std::string where = r.source.empty() ? std::string("material map") : r.source;
  if (!r.default_material.empty()) find_radio_material(r.default_material, r.user_materials, where + ": default_material");
  for (const auto* group : {&r.models, &r.links, &r.collisions, &r.meshes, &r.mesh_materials})
    for (const auto& [from, to] : *group) find_radio_material(to, r.user_materials, where + ": '" + from + "'");
}

}  // namespace rfidray::cli::gazebo
