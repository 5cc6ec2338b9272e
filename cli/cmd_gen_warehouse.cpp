// `rfidray gen-warehouse`: writes a scene as OBJ + MTL — the paper's warehouse, the small ground + wall scene, or
// a parametric warehouse (rows × racks × shelves, optional tessellation) of any size for benchmarks.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>
#include <sstream>

#include "core/error.h"
#include "io/atomic_file.h"
#include "raytrace/obj_loader.h"
#include "raytrace/warehouse.h"

namespace rfidray::cli {
namespace {

struct GenOptions {
  std::string output, preset = "parametric";
  WarehouseParams params;
  bool no_walls = false;
};

int run_gen(const GenOptions& o) {
  // Outputs first (before generating anything): regular files or new names, the .mtl distinct from the .obj.
  std::filesystem::path mtl = o.output;
  mtl.replace_extension(".mtl");
  if (mtl == std::filesystem::path(o.output))
    throw InputError("option -o: '" + clip(o.output) + "' would be both the OBJ and its .mtl (use a .obj name)");
  io::check_output_path(o.output, "the OBJ scene");
  io::check_output_path(mtl, "the MTL file");
  std::vector<TriangleMesh> meshes;
  if (o.preset == "paper") {
    meshes = paper_warehouse_meshes();
  } else if (o.preset == "ground-wall") {
    meshes = ground_and_wall_meshes();
  } else if (o.preset == "parametric") {
    WarehouseParams p = o.params;
    p.walls = !o.no_walls;
    try {
      meshes = generate_warehouse(p);  // checks the size estimate before allocating
    } catch (const InputError& e) {
      // Name the flag of the parameter (validate() names the WarehouseParams field).
      std::string msg = e.what();
      static const std::pair<const char*, const char*> kFlags[] = {
          {"rows", "--rows"}, {"racks_per_row", "--racks"}, {"shelves", "--shelves"},
          {"tessellation", "--tessellation"}, {"rack_length_m", "--rack-length"}, {"rack_depth_m", "--rack-depth"},
          {"shelf_spacing_m", "--shelf-spacing"}, {"aisle_m", "--aisle"}};
      for (const auto& [field, flag] : kFlags) {
        const std::string quoted = std::string("field '") + field + "'";
        if (msg.rfind(quoted, 0) == 0) msg = std::string("option ") + flag + " (" + field + ")" + msg.substr(quoted.size());
      }
      throw InputError("gen-warehouse --preset parametric: " + msg);
    }
  } else {
    throw InputError("option --preset: unknown preset '" + o.preset + "' (paper, ground-wall, parametric)");
  }
  // Both files complete or not at all (io/atomic_file.h): the OBJ streamed to a temporary and renamed, then
  // its .mtl; if the .mtl cannot be written the OBJ is removed again.
  std::ostringstream mtl_text;
  io::write_file_atomic(o.output, [&](std::ostream& out) { write_obj(out, mtl_text, mtl.filename().string(), meshes); },
                        "OBJ file");
  try {
    io::write_file_atomic(mtl, [&](std::ostream& out) { out << mtl_text.str(); }, "MTL file");
  } catch (...) {
    std::error_code ec;
    std::filesystem::remove(o.output, ec);
    throw;
  }
  size_t n = 0;
  for (const auto& m : meshes) n += m.triangle_count();
  std::printf("wrote %s: %zu meshes, %zu triangles\n", o.output.c_str(), meshes.size(), n);
  return 0;
}

}  // namespace

std::function<int()> setup_gen_warehouse(CLI::App& app) {
  auto o = std::make_shared<GenOptions>();
  CLI::App* cmd = app.add_subcommand("gen-warehouse", "Write a warehouse scene (OBJ + MTL): paper, ground-wall or parametric");
  cmd->add_option("-o,--output", o->output, "output .obj (a .mtl is written beside it)")->required();
  cmd->add_option("--preset", o->preset, "paper | ground-wall | parametric");
  cmd->add_option("--rows", o->params.rows, "parametric: rows of racks");
  cmd->add_option("--racks", o->params.racks_per_row, "parametric: racks per row");
  cmd->add_option("--shelves", o->params.shelves, "parametric: shelves per rack");
  cmd->add_option("--tessellation", o->params.tessellation, "parametric: split every rectangle n × n");
  cmd->add_option("--rack-length", o->params.rack_length_m, "parametric: rack length (m)");
  cmd->add_option("--rack-depth", o->params.rack_depth_m, "parametric: rack depth (m)");
  cmd->add_option("--shelf-spacing", o->params.shelf_spacing_m, "parametric: shelf spacing (m)");
  cmd->add_option("--aisle", o->params.aisle_m, "parametric: aisle width (m)");
  cmd->add_flag("--no-walls", o->no_walls, "parametric: no enclosing walls");
  return [o] { return run_gen(*o); };
}

}  // namespace rfidray::cli
