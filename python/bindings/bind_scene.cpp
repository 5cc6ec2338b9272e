// Scene, Endpoint, Path and Channel: the objects behind `rfidray link`, for Python. Scenes load through the
// same functions as the CLI (raytrace load_scene for OBJ files, io::load_world_source for worlds), channels
// through make_channel, endpoints and channel options through the scenario readers (io/scenario_yaml.h).
#include <pybind11/complex.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <optional>

#include "core/channel.h"
#include "core/channel_level.h"
#include "core/error.h"
#include "core/limits.h"
#include "core/reader.h"
#include "core/simulation.h"
#include "raytrace/channel_factory.h"
#include "io/checked_yaml.h"
#include "io/scenario_yaml.h"
#include "io/world_source.h"
#include "python/bindings/bindings.h"
#include "raytrace/material_map.h"
#include "raytrace/scene.h"
#include "core/number_text.h"

namespace rfidray::py {
namespace {

struct PyScene {
  std::shared_ptr<const Scene> scene;
  std::vector<std::string> files;
  std::vector<std::string> warnings;
  std::optional<Scenario> world;  // a world's antennas and tags (Scene.load of a .world / .sdf file)
};

struct PyChannel {
  std::shared_ptr<const Channel> channel;
  std::shared_ptr<const Scene> scene;  // nullptr for ideal
};

// A path with the two ends it joins, so it can be drawn.
struct PyPath {
  Path path;
  Vec3 antenna = Vec3::Zero();
  Vec3 tag = Vec3::Zero();
};

pyb::array_t<double> vec(const Vec3& v) {
  pyb::array_t<double> a(3);
  for (int k = 0; k < 3; ++k) a.mutable_at(k) = v[k];
  return a;
}

bool is_world_file(const std::filesystem::path& p) {
  const std::string ext = p.extension().string();
  return ext == ".world" || ext == ".sdf";
}

// An Endpoint, or a bare position (the defaults of `rfidray link`: isotropic 0 dBi, linear along local z).
Endpoint endpoint_from(pyb::handle h, const std::string& what) {
  if (pyb::isinstance<Endpoint>(h)) return h.cast<Endpoint>();
  YAML::Node map(YAML::NodeType::Map);
  map["position"] = to_yaml(h, "position");
  return io::parse_endpoint(map, what, "");
}

void check_frequency(double frequency_hz) {
  limits::check_range(frequency_hz, limits::kMinFrequencyHz, limits::kMaxFrequencyHz, "frequency_hz", "Hz");
}

void check_apart(const Vec3& antenna, const Vec3& tag, const std::string& what) {
  if (!((antenna - tag).norm() >= kMinLinkDistance_m))
    throw InputError(what + ": the tag is at the antenna (closer than 1 µm)");
}

PyScene load_scene_py(pyb::object source, std::optional<std::string> material,
                      std::optional<std::string> default_material, std::optional<double> thickness_m,
                      std::optional<std::filesystem::path> materials,
                      std::vector<std::filesystem::path> resource_path) {
  std::vector<std::filesystem::path> files;
  if (pyb::isinstance<pyb::str>(source) || pyb::hasattr(source, "__fspath__")) {
    files.push_back(source.cast<std::filesystem::path>());
  } else {
    for (auto item : source) files.push_back(item.cast<std::filesystem::path>());
  }
  if (files.empty()) throw InputError("Scene.load: no file given");
  PyScene out;
  for (const auto& f : files) out.files.push_back(f.string());
  if (files.size() == 1 && is_world_file(files[0])) {
    if (material || thickness_m)
      throw InputError("Scene.load " + files[0].string() +
                       ": a world's materials come from materials=FILE (and default_material=), not material=/thickness_m=");
    io::WorldSourceOptions o;
    o.file = files[0].string();
    for (const auto& dir : resource_path) o.resource_path.push_back(dir.string());
    if (materials) o.materials_file = materials->string();
    io::WorldSource world = io::load_world_source(o, default_material.value_or(""));
    out.scene = world.scene;
    out.warnings = world.warnings;
    for (const auto& n : world.notes) out.warnings.push_back("note: " + n);
    out.world = std::move(world.scenario);
    return out;
  }
  if (materials) throw InputError("Scene.load: materials=FILE is the material map of a world file (.world, .sdf)");
  if (!resource_path.empty()) throw InputError("Scene.load: resource_path is for world files (.world, .sdf)");
  MaterialAssignment assignment;
  if (material) {
    find_radio_material(*material, {}, "material");
    assignment.override_all = *material;
  }
  if (default_material) {
    find_radio_material(*default_material, {}, "default_material");
    assignment.default_material = *default_material;
  }
  if (thickness_m) {
    limits::check_range(*thickness_m, 0.0, 100.0, "thickness_m", "m");
    assignment.thickness_m = *thickness_m;
  }
  out.scene = load_scene(files, assignment, {}, &out.warnings);
  return out;
}

pyb::list endpoints_of(const PyScene& s, bool antennas) {
  pyb::list out;
  if (!s.world) return out;
  if (antennas)
    for (const AntennaSpec& a : s.world->antennas)
      out.append(pyb::make_tuple(a.reader.name, Endpoint{a.motion.pose, a.reader.pattern, a.reader.polarization}));
  else
    for (const TagSpec& t : s.world->tags)
      out.append(pyb::make_tuple(t.tag.name, Endpoint{t.motion.pose, t.tag.pattern, t.tag.polarization}));
  return out;
}

}  // namespace

void bind_scene(pyb::module_& m) {
  pyb::class_<PyScene>(m, "Scene", "A static radio scene: triangle meshes with radio materials and their BVH.")
      .def_static("load", &load_scene_py, pyb::arg("source"), pyb::kw_only(), pyb::arg("material") = pyb::none(),
                  pyb::arg("default_material") = pyb::none(), pyb::arg("thickness_m") = pyb::none(),
                  pyb::arg("materials") = pyb::none(), pyb::arg("resource_path") = std::vector<std::filesystem::path>{},
                  R"(Loads OBJ file(s) or a Gazebo world (.world/.sdf) as `rfidray link --scene/--world` does.

OBJ: usemtl names are radio materials; material= forces one material everywhere, default_material= covers
unknown names, thickness_m= sets every slab's thickness. World: materials= is its material map file (YAML),
resource_path= the model:// search directories. Raises ValueError (rfidray.InputError) naming file and line.)")
      .def_property_readonly("triangles", [](const PyScene& s) { return s.scene->triangle_count(); })
      .def_property_readonly("facets", [](const PyScene& s) { return s.scene->facets().size(); })
      .def_property_readonly("files", [](const PyScene& s) { return s.files; })
      .def_property_readonly("materials",
                             [](const PyScene& s) {
                               std::vector<std::string> names;
                               for (const RadioMaterial& mat : s.scene->materials()) names.push_back(mat.name);
                               return names;
                             },
                             "Radio material names, in the scene's material order.")
      .def_property_readonly("notes", [](const PyScene& s) { return s.scene->notes(); })
      .def_property_readonly("warnings", [](const PyScene& s) { return s.warnings; })
      .def_property_readonly("antennas", [](const PyScene& s) { return endpoints_of(s, true); },
                             "A world's antennas as (name, Endpoint) pairs (empty for OBJ scenes).")
      .def_property_readonly("tags", [](const PyScene& s) { return endpoints_of(s, false); },
                             "A world's tags as (name, Endpoint) pairs (empty for OBJ scenes).")
      .def("__repr__", [](const PyScene& s) {
        return "<rfidray.Scene " + std::to_string(s.scene->triangle_count()) + " triangles, " +
               std::to_string(s.scene->facets().size()) + " facets>";
      });

  pyb::class_<Endpoint>(m, "Endpoint", "One end of a link: pose, antenna pattern and polarization.")
      .def(pyb::init([](pyb::object position, pyb::object rpy_deg, pyb::object pattern, pyb::object polarization,
                        pyb::object gain_dbi) {
             YAML::Node map(YAML::NodeType::Map);
             map["position"] = to_yaml(position, "position");
             if (!rpy_deg.is_none()) map["rpy_deg"] = to_yaml(rpy_deg, "rpy_deg");
             if (!pattern.is_none()) map["pattern"] = to_yaml(pattern, "pattern");
             if (!polarization.is_none()) map["polarization"] = to_yaml(polarization, "polarization");
             if (!gain_dbi.is_none()) map["gain_dbi"] = to_yaml(gain_dbi, "gain_dbi");
             return io::parse_endpoint(map, "Endpoint", "");
           }),
           pyb::arg("position"), pyb::arg("rpy_deg") = pyb::none(), pyb::arg("pattern") = pyb::none(),
           pyb::arg("polarization") = pyb::none(), pyb::arg("gain_dbi") = pyb::none(),
           R"(position [x, y, z] m; rpy_deg [roll, pitch, yaw] (boresight = local +X); pattern and polarization
as in a scenario file ('isotropic' | 'dipole' | {kind: patch, gain_dbi: 8, beamwidth_deg: 60};
'linear' | 'rhcp' | 'lhcp' | {kind: linear, axis: [x, y, z]}). Defaults: isotropic 0 dBi, linear along z.)")
      .def_property_readonly("position", [](const Endpoint& e) { return vec(e.pose.position); })
      .def_property_readonly("quaternion",
                             [](const Endpoint& e) {
                               const Quat& q = e.pose.orientation;
                               return std::vector<double>{q.x(), q.y(), q.z(), q.w()};
                             },
                             "Orientation as [x, y, z, w].")
      .def_property_readonly("pattern", [](const Endpoint& e) { return std::string(to_string(e.pattern.kind)); })
      .def_property_readonly("gain_dbi", [](const Endpoint& e) { return e.pattern.peak_gain_dbi; })
      .def_property_readonly("polarization",
                             [](const Endpoint& e) { return std::string(to_string(e.polarization.kind)); })
      .def("__repr__", [](const Endpoint& e) {
        const Vec3& p = e.pose.position;
        return "<rfidray.Endpoint at (" + num(p.x()) + ", " + num(p.y()) + ", " + num(p.z()) + "), " +
               to_string(e.pattern.kind) + ", " + to_string(e.polarization.kind) + ">";
      });

  pyb::class_<PyPath>(m, "Path", "One propagation path of a link (core/path.h).")
      .def_property_readonly("kind", [](const PyPath& p) { return std::string(to_string(p.path.kind)); },
                             "'los' | 'blocked' | 'reflection'")
      .def_property_readonly("length_m", [](const PyPath& p) { return p.path.length_m; })
      .def_property_readonly("point", [](const PyPath& p) { return vec(p.path.point); },
                             "Reflection point, or the first crossing of a blocked path.")
      .def_property_readonly("points",
                             [](const PyPath& p) {
                               const bool bent = p.path.kind == PathKind::kReflection;
                               pyb::array_t<double> a({bent ? 3 : 2, 3});
                               const Vec3 corners[3] = {p.antenna, bent ? p.path.point : p.tag, p.tag};
                               for (int i = 0; i < (bent ? 3 : 2); ++i)
                                 for (int k = 0; k < 3; ++k) a.mutable_at(i, k) = corners[i][k];
                               return a;
                             },
                             "The polyline antenna → (reflection point →) tag, shape (2 or 3, 3).")
      .def_property_readonly("material", [](const PyPath& p) { return p.path.material; })
      .def_property_readonly("crossings", [](const PyPath& p) { return p.path.crossings; })
      .def_property_readonly("coefficient", [](const PyPath& p) { return p.path.coefficient; },
                             "Pattern gains, polarization match and Fresnel / transmission coefficients.")
      .def_property_readonly("contribution", [](const PyPath& p) { return p.path.contribution; },
                             "(λ / 4πL) · coefficient · e^{−jkL}: this path's share of the one-way h.")
      .def("__repr__", [](const PyPath& p) {
        return "<rfidray.Path " + std::string(to_string(p.path.kind)) + " " + num(p.path.length_m) + " m" +
               (p.path.material.empty() ? "" : " " + p.path.material) + ">";
      });

  pyb::class_<PyChannel>(m, "Channel", "A one-way channel of a level on a scene, as make_channel builds it.")
      .def(pyb::init([](std::optional<PyScene> scene, const std::string& level, pyb::kwargs options) {
             const ChannelLevel l = parse_channel_level(level, "level");
             YAML::Node map(YAML::NodeType::Map);
             for (auto item : options) {
               const std::string key = pyb::str(item.first).cast<std::string>();
               map[key] = to_yaml(item.second, "channel_options." + key);
             }
             const ChannelOptionsSpec spec = io::parse_channel_options(map, "Channel");
             PyChannel c;
             if (is_traced(l) && !scene)
               throw InputError("Channel: level '" + level + "' traces rays and needs a scene (Scene.load)");
             if (scene) c.scene = scene->scene;
             c.channel = make_channel(l, spec, c.scene);
             return c;
           }),
           pyb::arg("scene"), pyb::arg("level") = "single-bounce",
           R"(level: ideal | los | los+blocked | single-bounce (auto needs a run: use simulate()). Keyword options
are a scenario's channel_options: candidates, candidate_rays, candidate_spread, drop_below_db,
max_path_length_m, thin_post_max_width_m, double_diffraction_max_m. scene may be None for the ideal channel.)")
      .def_property_readonly("name", [](const PyChannel& c) { return c.channel->name(); })
      .def(
          "paths",
          [](const PyChannel& c, pyb::handle antenna, pyb::handle tag, double frequency_hz) {
            const Endpoint a = endpoint_from(antenna, "antenna");
            const Endpoint t = endpoint_from(tag, "tag");
            check_frequency(frequency_hz);
            check_apart(a.pose.position, t.pose.position, "Channel.paths");
            std::vector<Path> paths;
            {
              pyb::gil_scoped_release release;
              paths = c.channel->paths(a, t, frequency_hz);
            }
            std::vector<PyPath> out;
            for (Path& p : paths) out.push_back({std::move(p), a.pose.position, t.pose.position});
            return out;
          },
          pyb::arg("antenna"), pyb::arg("tag"), pyb::arg("frequency_hz") = ReaderParams{}.frequencies_hz.front(),
          "Every path of one link (noise-free), as `rfidray link --json` lists them; antenna and tag are Endpoints "
          "or positions [x, y, z].")
      .def(
          "one_way",
          [](const PyChannel& c, pyb::handle antenna, pyb::array_t<double, pyb::array::c_style | pyb::array::forcecast> tags,
             double frequency_hz, pyb::object tag) {
            const Endpoint a = endpoint_from(antenna, "antenna");
            Endpoint prototype;
            if (!tag.is_none()) prototype = endpoint_from(tag, "tag");
            check_frequency(frequency_hz);
            if (tags.ndim() != 2 || tags.shape(1) != 3)
              throw InputError("Channel.one_way: tags must be an (N, 3) array of positions (got " +
                               std::to_string(tags.ndim()) + " dimensions" +
                               (tags.ndim() >= 2 ? ", " + std::to_string(tags.shape(1)) + " columns" : std::string()) + ")");
            const size_t n = static_cast<size_t>(tags.shape(0));
            std::vector<Endpoint> ends(n, prototype);
            auto t = tags.unchecked<2>();
            for (size_t i = 0; i < n; ++i) {
              for (int k = 0; k < 3; ++k) {
                if (!limits::coordinate_ok(t(i, k)))
                  throw InputError("Channel.one_way: tags[" + std::to_string(i) + "]: coordinates must be finite and within ±" +
                                   num(limits::kMaxCoordinateM) + " m (got " + num(t(i, k)) + ")");
                ends[i].pose.position[k] = t(i, k);
              }
              check_apart(a.pose.position, ends[i].pose.position, "Channel.one_way: tags[" + std::to_string(i) + "]");
            }
            pyb::array_t<std::complex<double>> h(static_cast<pyb::ssize_t>(n));
            std::complex<double>* out = h.mutable_data();
            {
              pyb::gil_scoped_release release;  // the traced channel runs OpenMP over the tags
              c.channel->one_way(a, ends, frequency_hz, std::span<std::complex<double>>(out, n));
            }
            return h;
          },
          pyb::arg("antenna"), pyb::arg("tags"), pyb::arg("frequency_hz") = ReaderParams{}.frequencies_hz.front(),
          pyb::arg("tag") = pyb::none(),
          "One-way channels h (complex128, shape (N,)) from one antenna to N tag positions (an (N, 3) array); every "
          "tag takes the orientation, pattern and polarization of `tag` (an Endpoint; default: isotropic, linear "
          "along z). The GIL is released; the ray tracer runs OpenMP over the tags.")
      .def("__repr__", [](const PyChannel& c) { return "<rfidray.Channel " + c.channel->name() + ">"; });
}

}  // namespace rfidray::py
