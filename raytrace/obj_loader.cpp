#include "raytrace/obj_loader.h"

#include <tiny_obj_loader.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "core/error.h"
#include "core/limits.h"
#include "core/number_text.h"

namespace rfidray {
namespace {

// One `f` line as the validation pass saw it: tinyobjloader keeps faces in file order, so the k-th face of
// the concatenated shapes is the k-th record here; that is how `usemtl` names survive without a .mtl.
struct FaceRecord {
  size_t line = 0;
  int vertex_count = 0;
  uint32_t usemtl = 0;  // into ObjValidation::usemtl_names (a name copied per face was a fifth of a 1 M-face load)
};
struct ObjValidation {
  std::vector<FaceRecord> faces;
  std::vector<std::string> usemtl_names{std::string()};  // 0: before any `usemtl`
};

// The whitespace-separated tokens of `s` into `out` (cleared first: one vector for every line of a file).
void split_ws(std::string_view s, std::vector<std::string_view>& out) {
  out.clear();
  size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r')) ++i;
    size_t j = i;
    while (j < s.size() && s[j] != ' ' && s[j] != '\t' && s[j] != '\r') ++j;
    if (j > i) out.push_back(s.substr(i, j - i));
    i = j;
  }
}

bool parse_double(std::string_view t, double& v) {
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  return r.ec == std::errc() && r.ptr == t.data() + t.size() && std::isfinite(v);
}

bool parse_int(std::string_view t, long long& v) {
  if (!t.empty() && t.front() == '+') t.remove_prefix(1);
  const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
  return r.ec == std::errc() && r.ptr == t.data() + t.size();
}

// Validates the file line by line; returns the face records in file order.
ObjValidation validate_obj(const std::filesystem::path& path) {
  std::error_code ec;
  if (std::filesystem::exists(path, ec) && !std::filesystem::is_regular_file(path, ec))
    throw InputError(path.string() + ": cannot open OBJ file (not a regular file)");
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot open OBJ file");
  const std::string file = path.string();
  auto fail = [&](size_t line, const std::string& what) {
    return InputError(file + ":" + std::to_string(line) + ": " + what);
  };
  ObjValidation out;
  std::vector<FaceRecord>& faces = out.faces;
  std::string line;
  uint32_t usemtl = 0;
  long long nv = 0, nvt = 0, nvn = 0;
  size_t line_no = 0;
  std::vector<std::string_view> tok;
  while (std::getline(in, line)) {
    ++line_no;
    split_ws(line, tok);
    if (tok.empty() || tok[0].front() == '#') continue;
    const std::string_view key = tok[0];
    if (key == "v" || key == "vn" || key == "vt") {
      const size_t need = key == "vt" ? 1 : 3;
      if (tok.size() < need + 1) throw fail(line_no, "'" + std::string(key) + "' needs " + std::to_string(need) + " numbers");
      for (size_t i = 1; i < tok.size() && i <= 3 + (key == "v" ? 4 : 0); ++i) {
        double x;
        if (!parse_double(tok[i], x))
          throw fail(line_no, "malformed number '" + clip(tok[i]) + "' in '" + std::string(key) + "' line");
        if (key == "v" && i <= 3 && !limits::coordinate_ok(x))
          throw fail(line_no, "vertex coordinate " + num(x) + " m is outside ±" +
                                  num(limits::kMaxCoordinateM) + " m");
      }
      (key == "v" ? nv : key == "vt" ? nvt : nvn)++;
    } else if (key == "f") {
      if (tok.size() < 4) throw fail(line_no, "a face needs at least 3 vertices");
      // The OBJ parser counts a face's vertices in one byte.
      if (tok.size() - 1 > 255)
        throw fail(line_no, "a face with " + std::to_string(tok.size() - 1) +
                                " vertices; at most 255 per face (split it into smaller faces)");
      for (size_t i = 1; i < tok.size(); ++i) {
        std::string_view ref = tok[i];
        const long long counts[3] = {nv, nvt, nvn};
        for (int part = 0; part < 3; ++part) {
          const size_t slash = ref.find('/');
          const std::string_view idx = ref.substr(0, slash);
          if (!(part > 0 && idx.empty())) {
            long long k;
            if (!parse_int(idx, k) || k == 0)
              throw fail(line_no, "malformed face index '" + clip(tok[i]) + "'");
            const long long resolved = k > 0 ? k : counts[part] + k + 1;
            if (resolved < 1 || resolved > counts[part])
              throw fail(line_no, "face index " + std::to_string(k) + " out of range (" +
                                      std::to_string(counts[part]) + " defined so far) in '" + clip(tok[i]) + "'");
          }
          if (slash == std::string_view::npos) break;
          ref.remove_prefix(slash + 1);
          if (part == 2) throw fail(line_no, "malformed face index '" + clip(tok[i]) + "'");
        }
      }
      faces.push_back({line_no, static_cast<int>(tok.size() - 1), usemtl});
    } else if (key == "usemtl") {
      if (tok.size() < 2) throw fail(line_no, "'usemtl' without a material name");
      const auto& names = out.usemtl_names;
      usemtl = static_cast<uint32_t>(std::find(names.begin(), names.end(), tok[1]) - names.begin());
      if (usemtl == names.size()) out.usemtl_names.emplace_back(tok[1]);
    } else if (key == "mtllib") {
      // The OBJ parser reads the material library whole: a device or FIFO would never end.
      for (size_t i = 1; i < tok.size(); ++i) {
        const std::filesystem::path lib = path.parent_path() / std::string(tok[i]);
        if (std::filesystem::exists(lib, ec) && !std::filesystem::is_regular_file(lib, ec))
          throw fail(line_no, "mtllib '" + clip(tok[i]) + "': not a regular file");
      }
    }
  }
  return out;
}

std::vector<std::string> split_lines(const std::string& text, const std::string& prefix) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string l;
  while (std::getline(in, l))
    if (!l.empty()) out.push_back(prefix + l);
  return out;
}

uint32_t material_slot(TriangleMesh& mesh, const std::string& name) {
  for (size_t i = 0; i < mesh.material_names.size(); ++i)
    if (mesh.material_names[i] == name) return static_cast<uint32_t>(i);
  mesh.material_names.push_back(name);
  return static_cast<uint32_t>(mesh.material_names.size() - 1);
}

}  // namespace

ObjScene load_obj(const std::filesystem::path& path) {
  const ObjValidation validation = validate_obj(path);
  const std::vector<FaceRecord>& records = validation.faces;
  const std::string file = path.string();

  tinyobj::ObjReaderConfig config;
  config.triangulate = false;  // we fan-triangulate, keeping one face per `f` line
  config.vertex_color = false;
  config.mtl_search_path = path.parent_path().string();
  tinyobj::ObjReader reader;
  const bool ok = reader.ParseFromFile(file, config);
  ObjScene out;
  out.warnings = split_lines(reader.Warning(), file + ": ");
  if (!ok) throw InputError(file + ": " + (reader.Error().empty() ? "cannot parse OBJ" : reader.Error()));
  for (auto& e : split_lines(reader.Error(), file + ": ")) out.warnings.push_back(e);

  const auto& attrib = reader.GetAttrib();
  const size_t vertex_count = attrib.vertices.size() / 3;
  std::map<std::string, size_t> mesh_of_name;
  // Per mesh: global vertex → local index, holding only the vertices the mesh uses (a dense array per mesh
  // would cost meshes × vertices: quadratic for files with one `o` group per object).
  std::vector<std::unordered_map<int, uint32_t>> local_index;
  size_t k = 0;
  for (const auto& shape : reader.GetShapes()) {
    if (shape.mesh.num_face_vertices.empty()) continue;
    const std::string name = shape.name.empty() ? path.stem().string() : shape.name;
    auto [it, inserted] = mesh_of_name.emplace(name, out.meshes.size());
    if (inserted) {
      out.meshes.emplace_back().name = name;
      local_index.emplace_back();
    }
    TriangleMesh& mesh = out.meshes[it->second];
    auto& local = local_index[it->second];
    auto vertex = [&](const tinyobj::index_t& idx) {
      const int g = idx.vertex_index;
      if (g < 0 || static_cast<size_t>(g) >= vertex_count)
        throw InputError(file + ": face " + std::to_string(k) + " refers to a vertex the parser did not load");
      const auto [it, inserted] = local.try_emplace(g, static_cast<uint32_t>(mesh.vertices.size()));
      if (inserted)
        mesh.vertices.emplace_back(attrib.vertices[3 * g], attrib.vertices[3 * g + 1], attrib.vertices[3 * g + 2]);
      return it->second;
    };
    size_t offset = 0;
    for (const unsigned char n : shape.mesh.num_face_vertices) {
      if (k >= records.size() || records[k].vertex_count != n)
        throw InputError(file + (k < records.size() ? ":" + std::to_string(records[k].line) : std::string()) +
                         ": face " + std::to_string(k + 1) + " could not be matched to its line");
      const FaceRecord& rec = records[k++];
      const uint32_t mat = material_slot(mesh, validation.usemtl_names[rec.usemtl]);
      const uint32_t v0 = vertex(shape.mesh.indices[offset]);
      for (size_t i = 1; i + 1 < n; ++i) {
        mesh.triangles.push_back({v0, vertex(shape.mesh.indices[offset + i]), vertex(shape.mesh.indices[offset + i + 1])});
        mesh.triangle_material.push_back(mat);
      }
      offset += n;
    }
  }
  if (k != records.size())
    throw InputError(file + ":" + std::to_string(records[k].line) + ": face was not loaded by the OBJ parser");
  return out;
}

void write_obj(std::ostream& obj, std::ostream& mtl, const std::string& mtl_name, const std::vector<TriangleMesh>& meshes) {
  char buf[160];
  auto put = [&](std::ostream& out, int n) { out.write(buf, std::min<int>(n, sizeof buf - 1)); };
  put(obj, std::snprintf(buf, sizeof buf, "# rfidray scene: %zu meshes; usemtl names are radio material names\n", meshes.size()));
  obj << "mtllib " << mtl_name << "\n";
  std::map<std::string, int> all_materials;
  size_t base = 1;
  for (const TriangleMesh& m : meshes) {
    obj << "o " << m.name << "\n";
    for (const Vec3& v : m.vertices) {
      if (!v.allFinite())
        throw std::logic_error("internal error: mesh '" + m.name + "' has a non-finite vertex; OBJ not written");
      put(obj, std::snprintf(buf, sizeof buf, "v %.10g %.10g %.10g\n", v.x(), v.y(), v.z()));
    }
    int64_t current = -1;
    for (size_t t = 0; t < m.triangles.size(); ++t) {
      if (static_cast<int64_t>(m.triangle_material[t]) != current) {
        current = m.triangle_material[t];
        obj << "usemtl " << m.material_names[current] << "\n";
        all_materials.emplace(m.material_names[current], 0);
      }
      const auto& tri = m.triangles[t];
      put(obj, std::snprintf(buf, sizeof buf, "f %zu %zu %zu\n", base + tri[0], base + tri[1], base + tri[2]));
    }
    base += m.vertices.size();
  }
  mtl << "# Names are ITU-R P.2040 radio materials (raytrace/material_map.h); colours are for viewers only.\n";
  for (const auto& [name, unused] : all_materials) {
    const bool metal = name.find("metal") != std::string::npos;
    mtl << "newmtl " << name << "\nKd " << (metal ? "0.55 0.6 0.65" : "0.7 0.68 0.62") << "\n\n";
  }
}

void write_obj(const std::filesystem::path& path, const std::vector<TriangleMesh>& meshes) {
  std::filesystem::path mtl = path;
  mtl.replace_extension(".mtl");
  std::ofstream obj_out(path, std::ios::binary), mtl_out;
  if (!obj_out) throw InputError(path.string() + ": cannot write OBJ file");
  std::ostringstream mtl_text;
  write_obj(obj_out, mtl_text, mtl.filename().string(), meshes);
  obj_out.close();
  if (!obj_out) throw InputError(path.string() + ": cannot write OBJ file");
  mtl_out.open(mtl, std::ios::binary);
  mtl_out << mtl_text.str();
  mtl_out.close();
  if (!mtl_out) throw InputError(mtl.string() + ": cannot write MTL file");
}

}  // namespace rfidray
