#include "cli/planning.h"

#include "cli/number_list.h"

#include <fnmatch.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <sstream>

#include "cli/commands.h"
#include "cli/progress.h"
#include "core/error.h"
#include "core/limits.h"
#include "raytrace/channel_factory.h"
#include "io/scenario_yaml.h"
#include "io/tag_antenna_spec.h"
#include "io/tag_generators.h"
#include "parallel/ranks.h"
#include "core/thread_count.h"

namespace rfidray::cli {
namespace {

// --tag-antenna, --tag-chip, --tag-backing: every cell's tag becomes that antenna (core/tag_antenna.h).
void override_tag_antenna(const PlanningOptions& o, std::vector<TagParams>& params) {
  if (o.tag_antenna.empty()) {
    if (!o.tag_chip.empty() || !o.tag_backing.empty())
      throw InputError("options --tag-chip and --tag-backing need --tag-antenna");
    return;
  }
  const TagAntennaSpec antenna = io::parse_tag_antenna(o.tag_antenna, "option --tag-antenna");
  const TagChipSpec chip = io::parse_tag_chip(o.tag_chip.empty() ? "matched" : o.tag_chip, "option --tag-chip");
  const TagBackingSpec backing = io::parse_tag_backing(o.tag_backing.empty() ? "scene" : o.tag_backing, "option --tag-backing");
  validate(antenna, chip, backing, "option --tag");
  for (TagParams& t : params) t.antenna = antenna, t.chip = chip, t.backing = backing;
}

// At most this many cells in one map (a few hundred bytes each in flight).
constexpr size_t kMaxCells = 50'000'000;

std::vector<double> numbers(const std::string& text, const std::string& option, size_t count) {
  const std::vector<double> out = parse_number_list(text, option, /*coordinates=*/true);
  if (out.size() != count)
    throw InputError("option " + option + ": expected " + std::to_string(count) + " numbers separated by commas (got '" +
                     clip(text) + "')");
  return out;
}

// The xy extent of the scene's triangles (or of the scenario's antennas and tags when it has none).
std::array<double, 4> default_extent(const Planning& p) {
  double lo_x = INFINITY, lo_y = INFINITY, hi_x = -INFINITY, hi_y = -INFINITY;
  auto extend = [&](const Vec3& v) {
    lo_x = std::min(lo_x, v.x()), hi_x = std::max(hi_x, v.x()), lo_y = std::min(lo_y, v.y()), hi_y = std::max(hi_y, v.y());
  };
  if (p.scene && !p.scene->empty()) {
    extend(p.scene->bounds_lo());
    extend(p.scene->bounds_hi());
  }
  if (!std::isfinite(lo_x))
    throw InputError("the scenario has no scene to take the plane's extent from: give --extent X0,Y0,X1,Y1");
  return {lo_x, lo_y, hi_x, hi_y};
}

}  // namespace

void add_planning_options(CLI::App& cmd, PlanningOptions& o) {
  cmd.add_option("SCENARIO", o.scenario, "Scenario YAML file (or --world)");
  add_world_options(cmd, o.world);
  cmd.add_option("--plane", o.plane, "cells on a horizontal plane: z=HEIGHT (m), over --extent or the scene");
  cmd.add_option("--box", o.box, "cells in a box X0,Y0,Z0,X1,Y1,Z1 (m)");
  cmd.add_flag("--tags", o.tags, "the scenario's tags (listed and tag_sets) are the cells");
  cmd.add_option("--tag-filter", o.tag_filter, "with --tags: only tags whose name matches this shell pattern (e.g. 'east_*')");
  cmd.add_option("--tag-antenna", o.tag_antenna,
                 "the cells' tag as an antenna: dipole:LENGTH_M:RADIUS_M[:S_M] | table:FILE.csv (docs/tag-antenna.md)");
  cmd.add_option("--tag-chip", o.tag_chip, "with --tag-antenna: matched[:DESIGN_HZ] | series:R_OHM:C_F | parallel:R_OHM:C_F");
  cmd.add_option("--tag-backing", o.tag_backing, "with --tag-antenna: scene (default) | none | MATERIAL:DISTANCE_M (metal:0.01, water:0.005) | "
                 "dielectric:EPS_R:SIGMA_S_M:DISTANCE_M");
  cmd.add_option("--view", o.view, "maps seen from: top (x, y) | side (the cells' longer horizontal axis, and z)");
  cmd.add_option("--extent", o.extent, "plane extent X0,Y0,X1,Y1 (m); default: the scene's bounds");
  cmd.add_option("--step", o.step_m, "grid step (m) of --plane and --box");
  cmd.add_option("--channel", o.channel, "override the scenario's channel: " + channel_level_names());
  cmd.add_option("--model", o.model, "override every antenna's reader model: paper | physical");
  cmd.add_option("--pass-step", o.pass_step_s,
                 "moving antennas: evaluate the pass every S seconds (0: every tick, as simulate reads)");
  cmd.add_flag("--3d", o.three_d, "localization bound in 3-D (default: tag height known, 2-D)");
  cmd.add_option("--threads", o.threads, "OpenMP threads per process (0: default)");
  cmd.add_flag("--no-png", o.no_png, "write the CSV only");
  cmd.add_flag("-q,--quiet", o.quiet, "no summary, no progress line");
  cmd.add_flag("--progress", o.progress, "progress line even when stderr is not a terminal");
}

void make_output_dir(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(dir + ": cannot create output directory (" + ec.message() + ")");
}

Planning prepare_planning(const PlanningOptions& o) {
  Planning p;
  if (!o.world.file.empty()) {
    if (!o.scenario.empty()) throw InputError("give a SCENARIO file or --world FILE, not both");
    io::WorldSource world = io::load_world_source(o.world);
    if (!o.quiet && parallel::Ranks::world().root()) std::fprintf(stderr, "rfidray: %s\n", world.summary.c_str());
    p.scenario = std::move(world.scenario);
    p.scene = world.scene;
    p.source = o.world.file;
  } else {
    if (o.scenario.empty()) throw InputError("give a SCENARIO file (or --world FILE)");
    p.scenario = io::load_scenario(o.scenario);
    p.source = o.scenario;
  }
  if (!o.channel.empty()) p.scenario.channel = parse_channel_level(o.channel, "--channel");
  if (!o.model.empty()) {
    if (o.model != "paper" && o.model != "physical")
      throw InputError("option --model: expected paper or physical (got '" + clip(o.model) + "')");
    for (AntennaSpec& a : p.scenario.antennas)
      a.reader.model = o.model == "physical" ? ReaderModelKind::kPhysical : ReaderModelKind::kPaper;
  }
  if (!(std::isfinite(o.pass_step_s) && o.pass_step_s >= 0.0 && o.pass_step_s <= 1e6))
    throw InputError("option --pass-step: must be in [0, 1e6] s");
  if (o.threads < 0 || o.threads > 4096) throw InputError("option --threads: must be in [0, 4096]");
  const ThreadCount threads = startable_threads(o.threads, "--threads");
  if (!threads.note.empty()) std::fprintf(stderr, "rfidray: warning: %s\n", threads.note.c_str());
  p.threads = threads.threads;

  p.motion = build_motion(p.scenario);
  // Cells.
  const int modes = (!o.plane.empty()) + (!o.box.empty()) + (o.tags ? 1 : 0);
  if (modes != 1) throw InputError("give exactly one of --plane z=HEIGHT, --box X0,Y0,Z0,X1,Y1,Z1 and --tags");
  if (!(std::isfinite(o.step_m) && o.step_m > 0.0)) throw InputError("option --step: must be > 0 m");
  if (o.view != "top" && o.view != "side") throw InputError("option --view: expected top or side (got '" + clip(o.view) + "')");
  if (!o.tag_filter.empty() && !o.tags) throw InputError("option --tag-filter: only with --tags");
  if (p.scene == nullptr && !p.scenario.scene.meshes.empty())
    p.scene = load_scenario_scene(p.scenario, p.scenario.channel);
  if (o.tags) {
    if (p.scenario.tags.empty()) throw InputError("--tags: the scenario has no tags (add tags or tag_sets)");
    p.cells.params.clear();
    std::vector<double> heights;
    for (size_t i = 0; i < p.scenario.tags.size(); ++i) {
      const TagSpec& t = p.scenario.tags[i];
      if (!o.tag_filter.empty() && fnmatch(o.tag_filter.c_str(), t.tag.name.c_str(), 0) != 0) continue;
      p.cells.poses.push_back(p.motion.tags[i]->pose_at(t.start_s));  // a moving tag: where it starts
      p.cells.params.push_back(t.tag);
      p.cells.param_of.push_back(static_cast<uint32_t>(p.cells.params.size() - 1));
      heights.push_back(p.cells.poses.back().position.z());
    }
    if (p.cells.size() == 0) throw InputError("option --tag-filter: no tag of the scenario matches '" + clip(o.tag_filter) + "'");
    std::nth_element(heights.begin(), heights.begin() + heights.size() / 2, heights.end());
    p.plane_z = heights[heights.size() / 2];
    override_tag_antenna(o, p.cells.params);
  } else {
    // A grid cell's tag: the scenario's first tag's radio keys, else a scenario file's default tag.
    TagParams tag;
    tag.pattern = isotropic_pattern(tag.gain_dbi);
    if (!p.scenario.tags.empty()) tag = p.scenario.tags.front().tag;
    p.cells.params = {tag};
    override_tag_antenna(o, p.cells.params);
    io::TagGrid grid;
    grid.step_m = o.step_m;
    if (!o.plane.empty()) {
      if (o.plane.rfind("z=", 0) != 0) throw InputError("option --plane: expected z=HEIGHT (got '" + clip(o.plane) + "')");
      const double z = numbers(o.plane.substr(2), "--plane", 1)[0];
      const std::array<double, 4> e = o.extent.empty() ? default_extent(p) : [&] {
        const auto v = numbers(o.extent, "--extent", 4);
        return std::array<double, 4>{v[0], v[1], v[2], v[3]};
      }();
      // Cell centres: half a step in from the extent's edges.
      grid.min = Vec3(e[0] + 0.5 * o.step_m, e[1] + 0.5 * o.step_m, z);
      grid.max = Vec3(std::max(grid.min.x(), e[2] - 0.5 * o.step_m + 1e-9),
                      std::max(grid.min.y(), e[3] - 0.5 * o.step_m + 1e-9), z);
      p.plane_z = z;
      p.grid = true;
    } else {
      if (!o.extent.empty()) throw InputError("option --extent: only with --plane");
      const auto v = numbers(o.box, "--box", 6);
      grid.min = Vec3(v[0], v[1], v[2]);
      grid.max = Vec3(v[3], v[4], v[5]);
      p.plane_z = v[2];
    }
    std::array<size_t, 3> n{};
    std::vector<Vec3> pts = [&] {
      try {
        return io::grid_points(grid, !o.plane.empty() ? "--plane" : "--box", kMaxCells, &n);
      } catch (const InputError& e) {
        throw InputError(std::string("option ") + e.what());
      }
    }();
    p.nx = n[0];
    p.ny = n[1];
    p.cells.poses.reserve(pts.size());
    for (const Vec3& v : pts) p.cells.poses.push_back(Pose{v, Quat::Identity()});
  }

  // Channel. `channel: auto` samples the scenario's links; with no tags of its own, a sample of the cells.
  auto make = [&](const Scenario& sc, const SceneMotion& mo) {
    return p.scene ? make_channel(sc.channel, sc, mo, p.scene, &p.channel_report)
                   : make_channel(sc.channel, sc, mo, &p.channel_report);
  };
  if (p.scenario.channel == ChannelLevel::kAuto && p.scenario.tags.empty()) {
    Scenario sampled = p.scenario;
    const size_t want = std::max<size_t>(1, p.scenario.channel_options.auto_sample_links);
    const size_t stride = std::max<size_t>(1, p.cells.size() / want);
    for (size_t i = 0; i < p.cells.size(); i += stride) {
      TagSpec t;
      t.tag = p.cells.tag(i);
      t.tag.name = "cell" + std::to_string(i);
      t.motion.pose = p.cells.poses[i];
      sampled.tags.push_back(std::move(t));
    }
    p.channel = make(sampled, build_motion(sampled));
  } else {
    p.channel = make(p.scenario, p.motion);
  }
  p.ideal = std::make_unique<IdealChannel>();
  return p;
}

std::vector<planning::CoverageValues> sharded_coverage(const Planning& p, const std::vector<size_t>& antennas,
                                                 const PlanningOptions& o, const std::string& label,
                                                 bool information, bool validity) {
  const parallel::Ranks& ranks = parallel::Ranks::world();
  const auto [first, count] = ranks.share(p.cells.size());
  const planning::CoverageCells mine = p.cells.slice(first, count);
  planning::CoverageOptions opt;
  opt.pass_step_s = o.pass_step_s;
  opt.height_known = !o.three_d;
  opt.threads = p.threads;
  opt.information = information;
  opt.validity = validity;
  size_t work = 0;
  for (size_t a : antennas) work += planning::coverage_work(p.scenario, p.motion, a, mine.size(), opt);
  ProgressLine progress(label, work, "links", ranks.root() && ProgressLine::enabled_for(o.quiet, o.progress));
  opt.progress = [&](size_t n) { progress.advance(n); };
  const bool same = p.scenario.channel == ChannelLevel::kIdeal;
  // Per cell, per antenna: 6 values [+ 6 of information] (the gather's item is a cell, so shares concatenate in
  // cell order).
  const size_t kValues = information ? 12 : 6;
  std::vector<double> local;
  try {
    std::vector<planning::CoverageValues> v;
    for (size_t a : antennas)
      v.push_back(planning::coverage(p.scenario, p.motion, a, *p.channel, same ? *p.channel : *p.ideal, mine, opt));
    local.resize(mine.size() * antennas.size() * kValues);
    for (size_t i = 0; i < mine.size(); ++i)
      for (size_t k = 0; k < antennas.size(); ++k) {
        double* d = &local[(i * antennas.size() + k) * kValues];
        d[0] = v[k].read_probability[i], d[1] = v[k].rssi_dbm[i], d[2] = v[k].phase_error_rad[i],
        d[3] = v[k].localization_bound_m[i], d[4] = v[k].outside_validity[i], d[5] = v[k].validity_error[i];
        if (information) std::copy_n(&v[k].information[6 * i], 6, d + 6);
      }
  } catch (...) {
    (void)ranks.all_ok(false);  // the other ranks learn of it and stop too
    throw;
  }
  if (!ranks.all_ok(true)) throw InputError("another MPI rank failed (its error is above)");
  progress.finish();
  const std::vector<double> all = ranks.gather(local, p.cells.size(), antennas.size() * kValues);
  std::vector<planning::CoverageValues> out;
  if (!ranks.root()) return out;
  out.resize(antennas.size());
  for (auto& v : out) v.resize(p.cells.size(), information);
  for (size_t i = 0; i < p.cells.size(); ++i)
    for (size_t k = 0; k < antennas.size(); ++k) {
      const double* d = &all[(i * antennas.size() + k) * kValues];
      out[k].read_probability[i] = d[0], out[k].rssi_dbm[i] = d[1], out[k].phase_error_rad[i] = d[2],
      out[k].localization_bound_m[i] = d[3], out[k].outside_validity[i] = d[4], out[k].validity_error[i] = d[5];
      if (information) std::copy_n(d + 6, 6, &out[k].information[6 * i]);
    }
  return out;
}

io::FloorMap floor_map(const Planning& p, const std::vector<size_t>& antennas, const std::vector<double>& value,
                       const std::string& title, const std::string& label, const std::string& view) {
  io::FloorMap m;
  m.title = title;
  m.value_label = label;
  m.grid = p.grid;
  m.nx = p.nx;
  m.ny = p.ny;
  m.x.reserve(p.cells.size());
  m.y.reserve(p.cells.size());
  // The view: top (x, y), or side (the cells' longer horizontal axis, and z).
  int h = 0, v = 1;
  if (view == "side") {
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (const Pose& c : p.cells.poses)
      for (int k = 0; k < 2; ++k) lo[k] = std::min(lo[k], c.position[k]), hi[k] = std::max(hi[k], c.position[k]);
    h = hi[1] - lo[1] >= hi[0] - lo[0] ? 1 : 0;
    v = 2;
    m.grid = false;
  }
  const char* axis[3] = {"x (m)", "y (m)", "z (m)"};
  m.x_label = axis[h];
  m.y_label = axis[v];
  for (const Pose& c : p.cells.poses) m.x.push_back(c.position[h]), m.y.push_back(c.position[v]);
  m.value = value;
  if (p.scene && view == "top") m.walls = io::scene_cut(*p.scene, p.plane_z);
  for (size_t a : antennas) {
    const AntennaSpec& spec = p.scenario.antennas[a];
    const TrajectoryPtr& t = p.motion.antennas[a];
    const Pose pose = t->pose_at(spec.start_s);
    const Vec3 b = pose.orientation * Vec3::UnitX();
    m.antennas.push_back({spec.reader.name, Vec3(pose.position[h], pose.position[v], 0.0), Vec3(b[h], b[v], 0.0)});
    if (!t->is_static() && view == "top") {
      std::vector<Vec3> path;
      const double end = std::isfinite(t->end_time_s()) ? t->end_time_s() : scenario_duration_s(p.scenario, p.motion);
      for (int k = 0; k <= 400; ++k) path.push_back(t->pose_at(spec.start_s + (end - spec.start_s) * k / 400.0).position);
      m.paths.push_back(std::move(path));
    }
  }
  return m;
}

}  // namespace rfidray::cli
