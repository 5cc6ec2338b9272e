// SDF world → GazeboWorld with sdformat 12 (load_world in adapters/gazebo/gazebo_world.h).
#include <sdf/Collision.hh>
#include <sdf/Console.hh>
#include <sdf/Geometry.hh>
#include <sdf/Link.hh>
#include <sdf/Mesh.hh>
#include <sdf/Model.hh>
#include <sdf/ParserConfig.hh>
#include <sdf/Root.hh>
#include <sdf/Sensor.hh>
#include <sdf/World.hh>
#include <sdf/sdf.hh>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iostream>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "adapters/gazebo/gazebo_world.h"
#include "adapters/gazebo/resource_path.h"
#include "adapters/gazebo/rfid_sensors.h"
#include "core/error.h"
#include "core/limits.h"
#include "raytrace/mesh_file.h"
#include "raytrace/primitives.h"
#include "core/number_text.h"

namespace rfidray::gazebo {
namespace {

// A <pose> (resolved relative to its parent): finite, within the coordinate range (core/limits.h), so no
// inf/NaN vertex or antenna position goes further; `where` is "FILE:LINE: what".
Pose to_pose(const ignition::math::Pose3d& p, const std::string& where) {
  const double v[] = {p.Pos().X(), p.Pos().Y(), p.Pos().Z(), p.Rot().W(), p.Rot().X(), p.Rot().Y(), p.Rot().Z()};
  for (int i = 0; i < 3; ++i)
    if (!limits::coordinate_ok(v[i]))
      throw InputError(where + ": <pose> position (" + num(v[0]) + ", " + num(v[1]) + ", " +
                       num(v[2]) + ") is outside ±" + num(limits::kMaxCoordinateM) + " m");
  for (int i = 3; i < 7; ++i)
    if (!std::isfinite(v[i])) throw InputError(where + ": <pose> orientation is not finite");
  return Pose{Vec3(p.Pos().X(), p.Pos().Y(), p.Pos().Z()),
              Quat(p.Rot().W(), p.Rot().X(), p.Rot().Y(), p.Rot().Z()).normalized()};
}

std::string located(const std::optional<std::string>& file, const std::optional<int>& line, const std::string& fallback) {
  std::string f = file && !file->empty() ? *file : fallback;
  return line ? f + ":" + std::to_string(*line) : f;
}

std::string describe(const sdf::Error& e, const std::string& file) {
  return located(e.FilePath(), e.LineNumber(), file) + ": " + e.Message();
}

// sdformat's console text → one line per message, colour codes and source locations dropped, and
// "Line number=N" turned into FILE:N (the file the message names, else `file`).
std::vector<std::string> console_lines(const std::string& text, const std::string& file) {
  std::vector<std::string> out;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    std::string clean;
    for (size_t i = 0; i < line.size(); ++i) {
      if (line[i] == '\x1b') {  // ESC [ ... m
        while (i < line.size() && line[i] != 'm') ++i;
        continue;
      }
      clean += line[i];
    }
    if (clean.find_first_not_of(" \t") == std::string::npos) continue;
    if (clean.rfind("Error [", 0) == 0 || clean.rfind("Warning [", 0) == 0)
      if (const size_t close = clean.find("] "); close != std::string::npos) clean = clean.substr(close + 2);
    std::string where = file;
    if (const size_t f = clean.find("in file ["); f != std::string::npos)
      if (const size_t e = clean.find(']', f); e != std::string::npos) where = clean.substr(f + 9, e - f - 9);
    if (const size_t n = clean.find("Line number="); n != std::string::npos) {
      size_t k = n + 12;
      std::string digits;
      while (k < clean.size() && std::isdigit(static_cast<unsigned char>(clean[k]))) digits += clean[k++];
      if (!digits.empty()) where += ":" + digits;
    }
    out.push_back(where + ": " + clip(clean, 300));
  }
  return out;
}

// "; FILE:LINE: <sdf version="V"> is not a version such as 1.9" when the file's first <sdf> element has a version
// attribute that is not MAJOR.MINOR digits (what sdformat's converter parses with std::stoi); else "".
// Scanned by hand: libstdc++'s std::regex recurses per character and a 64 kB input can overflow the stack.
std::string sdf_version_remark(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const auto space = [](char c) { return std::isspace(static_cast<unsigned char>(c)) != 0; };
  size_t open = text.find("<sdf");
  while (open != std::string::npos && open + 4 < text.size() && !space(text[open + 4]))
    open = text.find("<sdf", open + 4);  // not <sdfx>
  if (open == std::string::npos) return "";
  const size_t close = text.find('>', open);
  const std::string tag = text.substr(open, close == std::string::npos ? std::string::npos : close - open);
  size_t k = tag.find("version");
  while (k != std::string::npos && !space(tag[k - 1])) k = tag.find("version", k + 7);
  if (k == std::string::npos) return "";
  k = tag.find_first_not_of(" \t\r\n", k + 7);
  if (k == std::string::npos || tag[k] != '=') return "";
  k = tag.find_first_not_of(" \t\r\n", k + 1);
  if (k == std::string::npos || (tag[k] != '"' && tag[k] != '\'')) return "";
  const size_t end = tag.find(tag[k], k + 1);
  if (end == std::string::npos) return "";
  const std::string version = tag.substr(k + 1, end - k - 1);
  const size_t dot = version.find('.');
  const auto digits = [](const std::string& d) {
    return !d.empty() && d.size() <= 4 &&
           std::all_of(d.begin(), d.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); });
  };
  if (dot != std::string::npos && digits(version.substr(0, dot)) && digits(version.substr(dot + 1))) return "";
  const auto line = 1 + std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(open), '\n');
  return "; " + file + ":" + std::to_string(line) + ": <sdf version=\"" + clip(version) +
         "\"> is not a version such as 1.9";
}

std::string element_where(const sdf::ElementPtr& e, const std::string& file) {
  const std::string f = e && !e->FilePath().empty() ? e->FilePath() : file;
  return e && e->LineNumber() ? f + ":" + std::to_string(*e->LineNumber()) : f;
}

// Names become CSV file names and ROS topic names.
void check_antenna_name(const std::string& name, const std::string& where) {
  bool ok = !name.empty() && name[0] != '.' && name != "tags" && name != "tags_trajectory";
  for (char c : name) ok = ok && (std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.');
  if (!ok)
    throw InputError(where + ": antenna sensor name '" + clip(name) +
                     "' must be letters, digits and _ - . (it names the CSV file and the ROS topic)");
}

class Importer {
 public:
  Importer(const WorldOptions& o) : options_(o), dirs_(resource_dirs(o.resource_path)) {}

  GazeboWorld run() {
    w_.file = options_.file;
    if (!std::filesystem::is_regular_file(options_.file))
      throw InputError(options_.file + ": cannot open world file (" +
                       (std::filesystem::exists(options_.file) ? "not a file" : "no such file") + ")");
    load_rules();
    sdf::ParserConfig config;
    for (const auto& d : dirs_) config.AddURIPath("model://", d.string());
    // <include> URIs the path map does not resolve (package://, relative) go through our resolver.
    config.SetFindCallback([this](const std::string& uri) -> std::string {
      try {
        return resolve_uri(uri, std::filesystem::path(options_.file).parent_path(), dirs_).string();
      } catch (const InputError&) {
        return "";
      }
    });
    sdf::Root root;
    // sdformat prints some errors (malformed XML, with its line) on its console instead of returning them:
    // capture them so the message below carries them, located.
    std::ostringstream console;
    sdf::Errors errors;
    {
      std::streambuf* const saved = std::cerr.rdbuf(console.rdbuf());
      try {
        errors = root.Load(options_.file, config);
      } catch (const InputError&) {
        std::cerr.rdbuf(saved);
        throw;
      } catch (const std::exception& e) {
        // sdformat 12 throws std::invalid_argument ("stoi") from its version converter when <sdf version="...">
        // is not two numbers (e.g. "1.a", "1..6"): a bad file, not a crash.
        std::cerr.rdbuf(saved);
        throw InputError(options_.file + ": not a usable SDF world: sdformat stopped reading it (" + clip(e.what()) +
                         ")" + sdf_version_remark(options_.file));
      } catch (...) {
        std::cerr.rdbuf(saved);
        throw;
      }
      std::cerr.rdbuf(saved);
    }
    const std::vector<std::string> console_errors = console_lines(console.str(), options_.file);
    std::string fatal;
    for (const sdf::Error& e : errors) {
      const bool unreadable = e.Code() == sdf::ErrorCode::FILE_READ || e.Code() == sdf::ErrorCode::STRING_READ;
      if (unreadable) fatal += "\n  " + describe(e, options_.file);
      // sdformat adds this one after any error inside a world; the error itself says more.
      else if (e.Message() != "Failed to load a world.") w_.warnings.push_back(describe(e, options_.file));
    }
    if (!fatal.empty() || root.WorldCount() == 0) {
      std::string all;
      for (const std::string& l : console_errors) all += "\n  " + l;
      all += fatal;
      if (fatal.empty())
        for (const sdf::Error& e : errors) all += "\n  " + describe(e, options_.file);
      throw InputError(options_.file + ": not a usable SDF world" +
                       (root.WorldCount() == 0 && fatal.empty() ? std::string(" (no <world> element)") : std::string()) +
                       all);
    }
    std::cerr << console.str();  // a usable world: sdformat's console remarks pass through as before
    if (root.WorldCount() > 1)
      w_.warnings.push_back(options_.file + ": " + std::to_string(root.WorldCount()) + " worlds; using the first");
    const sdf::World* world = root.WorldByIndex(0);
    w_.name = world->Name();
    for (uint64_t i = 0; i < world->ModelCount(); ++i) model(*world->ModelByIndex(i), -1, "");
    finish();
    return std::move(w_);
  }

 private:
  void load_rules() {
    if (!options_.materials_file.empty()) rules_ = load_material_rules(options_.materials_file);
    if (!options_.default_material.empty()) {
      rules_.default_material = options_.default_material;
      check_material_rules(rules_);
    }
  }

  void model(const sdf::Model& m, int parent, const std::string& scope) {
    Entity e;
    e.kind = Entity::Kind::kModel;
    e.name = m.Name();
    e.scoped_name = scope.empty() ? m.Name() : scope + "::" + m.Name();
    e.parent = parent;
    e.is_static = m.Static() || (parent >= 0 && w_.entities[parent].is_static);
    ignition::math::Pose3d p;
    const sdf::Errors errs = m.SemanticPose().Resolve(p);  // relative to the parent (world or model)
    for (const sdf::Error& err : errs) w_.warnings.push_back(describe(err, options_.file) + " (model '" + e.scoped_name + "')");
    e.pose = to_pose(p, element_where(m.Element(), options_.file) + ": model '" + e.scoped_name + "'");
    const int index = static_cast<int>(w_.entities.size());
    w_.entities.push_back(e);
    for (uint64_t i = 0; i < m.LinkCount(); ++i) link(*m.LinkByIndex(i), index, e.scoped_name);
    for (uint64_t i = 0; i < m.ModelCount(); ++i) model(*m.ModelByIndex(i), index, e.scoped_name);
  }

  void link(const sdf::Link& l, int model_index, const std::string& scope) {
    Entity e;
    e.kind = Entity::Kind::kLink;
    e.name = l.Name();
    e.scoped_name = scope + "::" + l.Name();
    e.parent = model_index;
    e.is_static = w_.entities[model_index].is_static;
    ignition::math::Pose3d p;
    for (const sdf::Error& err : l.SemanticPose().Resolve(p))
      w_.warnings.push_back(describe(err, options_.file) + " (link '" + e.scoped_name + "')");
    e.pose = to_pose(p, element_where(l.Element(), options_.file) + ": link '" + e.scoped_name + "'");
    const size_t index = w_.entities.size();
    w_.entities.push_back(e);
    for (uint64_t i = 0; i < l.CollisionCount(); ++i) collision(*l.CollisionByIndex(i), index);
    sensors(l, index);
  }

  void collision(const sdf::Collision& c, size_t link_index) {
    const std::string scoped = w_.entities[link_index].scoped_name + "::" + c.Name();
    const std::string where = element_where(c.Element(), options_.file) + ": collision '" + scoped + "'";
    ignition::math::Pose3d p;
    for (const sdf::Error& err : c.SemanticPose().Resolve(p)) w_.warnings.push_back(describe(err, options_.file) + " (" + scoped + ")");
    const Pose pose = to_pose(p, where);
    const sdf::Geometry* g = c.Geom();
    Collision out;
    out.link = link_index;
    out.scoped_name = scoped;
    Vec3 scale = Vec3::Ones();
    std::string mesh_file, mesh_uri;
    switch (g->Type()) {
      case sdf::GeometryType::BOX: {
        const auto s = g->BoxShape()->Size();
        out.mesh = box_mesh(Vec3(s.X(), s.Y(), s.Z()));
        out.geometry = "box";
        break;
      }
      case sdf::GeometryType::CYLINDER:
        out.mesh = cylinder_mesh(g->CylinderShape()->Radius(), g->CylinderShape()->Length());
        out.geometry = "cylinder";
        break;
      case sdf::GeometryType::SPHERE:
        out.mesh = sphere_mesh(g->SphereShape()->Radius());
        out.geometry = "sphere";
        break;
      case sdf::GeometryType::PLANE: {
        const auto n = g->PlaneShape()->Normal();
        auto s = g->PlaneShape()->Size();
        // Gazebo collides with planes as if infinite; SDF's <size> (default 1 × 1) is for visuals. We keep
        // a size the world gives, and make the default one a 1 km square, as a stand-in for infinite.
        if (s.X() == 1.0 && s.Y() == 1.0) {
          s.Set(1000.0, 1000.0);
          w_.notes.push_back(where + ": plane without <size> (infinite in Gazebo): 1 km x 1 km");
        }
        out.mesh = plane_mesh(Vec3(n.X(), n.Y(), n.Z()), s.X(), s.Y());
        out.geometry = "plane";
        break;
      }
      case sdf::GeometryType::MESH: {
        const sdf::Mesh* m = g->MeshShape();
        mesh_uri = m->Uri();
        const std::filesystem::path base =
            std::filesystem::path(m->FilePath().empty() ? options_.file : m->FilePath()).parent_path();
        std::filesystem::path file;
        try {
          file = resolve_uri(mesh_uri, base, dirs_);
        } catch (const InputError& err) {
          throw InputError(where + ": mesh " + err.what());
        }
        mesh_file = file.string();
        auto it = mesh_cache_.find(mesh_file);
        if (it == mesh_cache_.end()) {
          try {
            it = mesh_cache_.emplace(mesh_file, load_mesh_file(file, &w_.warnings)).first;
          } catch (const InputError& err) {
            throw InputError(where + ": " + err.what());
          }
        }
        out.mesh = it->second;
        const auto s = m->Scale();
        scale = Vec3(s.X(), s.Y(), s.Z());
        if (!m->Submesh().empty())
          w_.warnings.push_back(where + ": <submesh> '" + m->Submesh() + "' not supported; the whole mesh is used");
        out.geometry = "mesh:" + file.filename().string();
        break;
      }
      default:
        w_.warnings.push_back(where + ": geometry type not supported (box, cylinder, sphere, plane, mesh); skipped");
        return;
    }
    out.mesh.name = scoped;
    for (int k = 0; k < 3; ++k)
      if (!(std::isfinite(scale[k]) && scale[k] > 0.0 && scale[k] <= 1e6))
        throw InputError(where + ": <scale> must be in (0, 1e6] (got " + num(scale[k]) + ")");
    out.mesh.transform(pose, scale);
    for (const Vec3& v : out.mesh.vertices)
      if (!(limits::coordinate_ok(v.x()) && limits::coordinate_ok(v.y()) && limits::coordinate_ok(v.z())))
        throw InputError(where + ": a vertex lands at (" + num(v.x()) + ", " + num(v.y()) + ", " +
                         num(v.z()) + "), outside ±" + num(limits::kMaxCoordinateM) + " m");
    // The most specific material rule for this surface, if any (adapters/gazebo/material_rules.h).
    std::string material;
    auto rule = [&](const std::map<std::string, std::string>& m, const std::string& key) {
      if (!material.empty()) return;
      if (auto it = m.find(key); it != m.end()) {
        material = it->second;
        used_rules_.insert(&it->first);
      }
    };
    rule(rules_.collisions, scoped);
    rule(rules_.links, w_.entities[link_index].scoped_name);
    for (int e = w_.entities[link_index].parent; e >= 0 && material.empty(); e = w_.entities[e].parent) {
      rule(rules_.models, w_.entities[e].scoped_name);
      rule(rules_.models, w_.entities[e].name);
    }
    if (!mesh_file.empty()) {
      rule(rules_.meshes, mesh_uri);
      rule(rules_.meshes, std::filesystem::path(mesh_file).filename().string());
    }
    if (!material.empty()) w_.materials.by_mesh[scoped] = material;
    w_.collisions.push_back(std::move(out));
  }

  void sensors(const sdf::Link& l, size_t link_index) {
    const std::string& link_name = w_.entities[link_index].scoped_name;
    for (sdf::ElementPtr s = l.Element()->GetElementImpl("sensor"); s; s = s->GetNextElement("sensor")) {
      const RfidSensorKind kind = rfid_sensor_kind(s);
      if (kind == RfidSensorKind::kNone) continue;
      const std::string name = s->GetAttribute("name") ? s->GetAttribute("name")->GetAsString() : "";
      const std::string where = element_where(s, options_.file) + ": sensor '" + name + "'";
      Mount mount;
      mount.entity = link_index;
      mount.sensor = name;
      mount.line = s->LineNumber().value_or(0);
      if (const sdf::Sensor* dom = l.SensorByName(name)) {
        ignition::math::Pose3d p;
        for (const sdf::Error& err : dom->SemanticPose().Resolve(p)) w_.warnings.push_back(where + ": " + err.Message());
        mount.pose = to_pose(p, where);
      }
      if (kind == RfidSensorKind::kAntenna) {
        check_antenna_name(name, where);
        AntennaSpec a;
        a.reader = antenna_params(s, where, w_.notes, w_.warnings);
        a.reader.name = name;
        a.source_line = mount.line;
        mount.frame = antenna_tf_frame(s);
        for (size_t i = 0; i < w_.scenario.antennas.size(); ++i)
          if (w_.scenario.antennas[i].reader.name == name)
            throw InputError(where + ": a second antenna named '" + name + "' (the first is on link '" +
                             w_.entities[w_.antenna_mounts[i].entity].scoped_name + "'); antenna names must be unique");
        w_.scenario.antennas.push_back(std::move(a));
        w_.antenna_mounts.push_back(mount);
      } else {
        TagSpec t;
        t.tag = tag_params(s, where, w_.notes, w_.warnings);
        t.tag.name = link_name;
        t.source_line = mount.line;
        for (size_t i = 0; i < w_.scenario.tags.size(); ++i)
          if (w_.scenario.tags[i].tag.name == link_name)
            throw InputError(where + ": link '" + link_name + "' carries a second tag; tags are named after their link "
                             "(as the seed plugin does), so give each tag its own link");
        w_.scenario.tags.push_back(std::move(t));
        w_.tag_mounts.push_back(mount);
      }
    }
  }

  void finish() {
    if (w_.scenario.antennas.empty())
      w_.notes.push_back(options_.file + ": no RFID antenna (sensor type \"rfid\", or type \"custom\" with <rfid_antenna>)");
    w_.scenario.source = options_.file;
    w_.place_sensors();
    MaterialAssignment& m = w_.materials;
    m.user_materials = rules_.user_materials;
    m.by_material = rules_.mesh_materials;
    m.default_material = rules_.default_material;
    if (m.default_material.empty() && rules_.source.empty()) {
      m.default_material = "concrete";
      w_.notes.push_back(options_.file + ": no material map: surfaces without a radio material name are 'concrete' "
                         "(--materials FILE maps models, links and meshes)");
    }
    for (const auto* group : {&rules_.models, &rules_.links, &rules_.collisions, &rules_.meshes})
      for (const auto& [from, to] : *group)
        if (!used_rules_.count(&from))
          w_.notes.push_back(rules_.source + ": rule '" + from + ": " + to + "' matches nothing in the world");
  }

  const WorldOptions& options_;
  std::vector<std::filesystem::path> dirs_;
  MaterialRules rules_;
  GazeboWorld w_;
  std::map<std::string, TriangleMesh> mesh_cache_;
  std::set<const std::string*> used_rules_;
};

}  // namespace

GazeboWorld load_world(const WorldOptions& options) { return Importer(options).run(); }

}  // namespace rfidray::gazebo
