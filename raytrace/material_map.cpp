#include "raytrace/material_map.h"

#include <algorithm>
#include <cctype>
#include <optional>

#include "core/error.h"

namespace rfidray {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

std::optional<RadioMaterial> lookup(const std::string& name, const std::vector<RadioMaterial>& user) {
  for (const RadioMaterial& m : user)
    if (m.name == name) return m;
  return builtin_material(lower(name));
}

std::string known_names(const std::vector<RadioMaterial>& user) {
  std::string s;
  for (const RadioMaterial& m : user) s += (s.empty() ? "" : ", ") + m.name;
  for (const std::string& n : builtin_material_names()) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

RadioMaterial find_radio_material(const std::string& name, const std::vector<RadioMaterial>& user,
                                  const std::string& context) {
  if (auto m = lookup(name, user)) return *m;
  throw InputError(context + ": unknown radio material '" + name + "' (known: " + known_names(user) + ")");
}

ResolvedMaterials resolve_materials(const std::vector<TriangleMesh>& meshes, const MaterialAssignment& a) {
  ResolvedMaterials out;
  auto index_of = [&](RadioMaterial m) {
    if (a.thickness_m >= 0.0) m.thickness_m = a.thickness_m;
    if (a.solid && !m.perfect_conductor) m.solid = true;
    for (size_t i = 0; i < out.materials.size(); ++i)
      if (out.materials[i].name == m.name) return static_cast<uint32_t>(i);
    out.materials.push_back(std::move(m));
    return static_cast<uint32_t>(out.materials.size() - 1);
  };
  for (const auto& entry : a.by_mesh) {
    const std::string& mesh = entry.first;  // not a structured binding: clang 14 cannot capture those
    const bool used = std::any_of(meshes.begin(), meshes.end(), [&](const TriangleMesh& m) { return m.name == mesh; });
    if (!used) out.notes.push_back("material override for mesh '" + mesh + "' matches no mesh of the scene");
  }
  out.per_triangle.resize(meshes.size());
  for (size_t mi = 0; mi < meshes.size(); ++mi) {
    const TriangleMesh& mesh = meshes[mi];
    // Resolve each of the mesh's material names once.
    std::vector<uint32_t> slot(mesh.material_names.size());
    for (size_t k = 0; k < mesh.material_names.size(); ++k) {
      const std::string& usemtl = mesh.material_names[k];
      const std::string where = "mesh '" + mesh.name + "'" + (usemtl.empty() ? "" : " (usemtl '" + usemtl + "')");
      std::string name;
      if (!a.override_all.empty()) {
        name = a.override_all;
      } else if (auto it = a.by_mesh.find(mesh.name); it != a.by_mesh.end()) {
        name = it->second;
      } else if (auto jt = a.by_material.find(usemtl); jt != a.by_material.end()) {
        name = jt->second;
      } else if (lookup(usemtl, a.user_materials)) {
        name = usemtl;
      } else if (!a.default_material.empty()) {
        name = a.default_material;
        out.notes.push_back(where + ": " + (usemtl.empty() ? "no usemtl" : "not a radio material") +
                            ", using default '" + name + "'");
      } else {
        throw InputError(where + ": " + (usemtl.empty() ? "no material (no usemtl)" : "unknown radio material '" + usemtl + "'") +
                         "; map it in the scenario or set a default material (known: " + known_names(a.user_materials) + ")");
      }
      slot[k] = index_of(find_radio_material(name, a.user_materials, where));
    }
    auto& ids = out.per_triangle[mi];
    ids.resize(mesh.triangles.size());
    for (size_t t = 0; t < ids.size(); ++t) ids[t] = slot[mesh.triangle_material[t]];
  }
  return out;
}

}  // namespace rfidray
