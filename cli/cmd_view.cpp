// `rfidray view`: a scene and the traced paths of its links as one self-contained HTML page (io/view_html.h).
// The paths come from the channel `simulate` and `link` use (make_channel on the same scene and options).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <set>
#include <sstream>

#include "cli/commands.h"
#include "core/error.h"
#include "core/limits.h"
#include "core/simulation.h"
#include "io/atomic_file.h"
#include "raytrace/channel_factory.h"
#include "io/checked_yaml.h"
#include "io/scenario_yaml.h"
#include "io/view_html.h"
#include "io/world_source.h"
#include "raytrace/material_map.h"
#include "raytrace/scene.h"
#include "core/number_text.h"

namespace rfidray::cli {
namespace {

struct ViewOptions {
  std::string scenario;
  std::vector<std::string> scene;  // OBJ files instead of a scenario
  std::string default_material;
  std::vector<std::string> antennas, tags;  // X,Y,Z with --scene; names with a scenario or world
  std::optional<double> time_s;
  std::optional<uint64_t> tick;
  std::string level;  // --channel; "" = the scenario's channel, or single-bounce
  double frequency_hz = ReaderParams{}.frequencies_hz.front();
  std::string output = "view.html";
  io::WorldSourceOptions world;
};

// X,Y,Z through the scenario reader (numbers, finite, within the coordinate range), link's defaults otherwise.
Endpoint endpoint_at(const std::string& text, const std::string& option) {
  YAML::Node map(YAML::NodeType::Map);
  YAML::Node position(YAML::NodeType::Sequence);
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) position.push_back(item);
  map["position"] = position;
  return io::parse_endpoint(map, "option " + option + " '" + clip(text) + "'", "");
}

// Keeps the named entries (all when `wanted` is empty); an unknown name is an error listing the known ones.
std::vector<size_t> select(const std::vector<std::string>& names, const std::vector<std::string>& wanted,
                           const std::string& option) {
  std::vector<size_t> out;
  if (wanted.empty()) {
    for (size_t i = 0; i < names.size(); ++i) out.push_back(i);
    return out;
  }
  for (const std::string& w : wanted) {
    size_t i = 0;
    while (i < names.size() && names[i] != w) ++i;
    if (i == names.size()) {
      std::string known;
      for (const std::string& n : names) known += (known.empty() ? "" : ", ") + n;
      throw InputError("option " + option + ": no '" + clip(w) + "' (known: " + (known.empty() ? "none" : known) + ")");
    }
    out.push_back(i);
  }
  return out;
}

int run_view(const ViewOptions& o) {
  const int sources = !o.scenario.empty() + !o.scene.empty() + !o.world.file.empty();
  if (sources != 1) throw InputError("give one of SCENARIO, --scene FILE.obj or --world FILE");
  if (o.time_s && o.tick) throw InputError("give --time or --tick, not both");
  if (o.time_s && !(*o.time_s >= 0.0 && std::isfinite(*o.time_s))) throw field_error("--time", "must be a finite number >= 0");
  io::check_output_path(o.output, "view HTML");
  io::ViewInput view;
  std::vector<std::string> warnings;
  std::shared_ptr<const Scene> scene;
  std::unique_ptr<Channel> channel;

  if (!o.scene.empty()) {
    // Bare positions, every antenna with every tag, as `rfidray link` takes them.
    if (o.antennas.empty() || o.tags.empty()) throw InputError("--scene: give --antenna X,Y,Z and --tag X,Y,Z (repeatable)");
    if (o.time_s || o.tick) throw InputError("--time/--tick need a SCENARIO (a --scene has no motion)");
    limits::check_range(o.frequency_hz, limits::kMinFrequencyHz, limits::kMaxFrequencyHz, "--frequency", "Hz");
    MaterialAssignment assignment;
    if (!o.default_material.empty()) {
      find_radio_material(o.default_material, {}, "option --default-material");
      assignment.default_material = o.default_material;
    }
    scene = load_scene(std::vector<std::filesystem::path>(o.scene.begin(), o.scene.end()), assignment, {}, &warnings);
    for (const auto& w : warnings) std::cerr << "rfidray: warning: " << w << "\n";
    const ChannelLevel level = parse_channel_level(o.level.empty() ? "single-bounce" : o.level, "--channel");
    channel = make_channel(level, ChannelOptionsSpec{}, scene);
    std::vector<Endpoint> ants, tags;
    for (size_t i = 0; i < o.antennas.size(); ++i) {
      ants.push_back(endpoint_at(o.antennas[i], "--antenna"));
      view.antennas.push_back({"antenna" + std::to_string(i), ants.back().pose});
    }
    for (size_t i = 0; i < o.tags.size(); ++i) {
      tags.push_back(endpoint_at(o.tags[i], "--tag"));
      view.tags.push_back({"tag" + std::to_string(i), tags.back().pose});
    }
    for (size_t a = 0; a < ants.size(); ++a)
      for (size_t t = 0; t < tags.size(); ++t) {
        if (!((ants[a].pose.position - tags[t].pose.position).norm() >= kMinLinkDistance_m))
          throw InputError("--tag " + o.tags[t] + " is at --antenna " + o.antennas[a]);
        view.links.push_back({a, t, o.frequency_hz, ants[a].pose.position, tags[t].pose.position,
                              channel->paths(ants[a], tags[t], o.frequency_hz)});
      }
    view.title = o.scene.front();
  } else {
    // A scenario or a world: its antennas and the tags present at the chosen time, with their radio keys.
    Scenario scenario;
    if (!o.world.file.empty()) {
      const io::WorldSource world = io::load_world_source(o.world, o.default_material);
      std::fprintf(stderr, "rfidray: %s\n", world.summary.c_str());
      io::print_world_remarks(world);
      scenario = world.scenario;
      scene = world.scene;
      view.title = o.world.file;
    } else {
      if (!o.default_material.empty()) throw InputError("--default-material is for --scene / --world (a scenario says default_material)");
      scenario = io::load_scenario(o.scenario);
      scene = load_scene(scenario.scene, scenario.source, {}, &warnings);
      for (const auto& w : warnings) std::cerr << "rfidray: warning: " << w << "\n";
      view.title = o.scenario;
    }
    if (!o.level.empty()) scenario.channel = parse_channel_level(o.level, "--channel");
    else if (!is_traced(scenario.channel)) scenario.channel = ChannelLevel::kSingleBounce;  // paths worth seeing
    const SceneMotion motion = build_motion(scenario);
    std::vector<std::string> report;
    channel = make_channel(scenario.channel, scenario, motion, scene, &report);
    for (const auto& line : report) std::fprintf(stderr, "rfidray: %s\n", line.c_str());

    std::vector<std::string> antenna_names, tag_names;
    for (const AntennaSpec& a : scenario.antennas) antenna_names.push_back(a.reader.name);
    for (const TagSpec& t : scenario.tags) tag_names.push_back(t.tag.name);
    const std::vector<size_t> ants = select(antenna_names, o.antennas, "--antenna");
    const std::vector<size_t> tags = select(tag_names, o.tags, "--tag");
    if (ants.empty()) throw InputError(view.title + ": no antenna to show");
    // --tick N is the N-th read tick of the first antenna shown (t = N / its update rate).
    const double t_s = o.tick ? static_cast<double>(*o.tick) / scenario.antennas[ants.front()].reader.update_rate_hz
                              : o.time_s.value_or(0.0);
    std::vector<size_t> present;
    for (size_t t : tags)
      if (t_s >= scenario.tags[t].start_s) present.push_back(t);
    for (size_t t : present) view.tags.push_back({tag_names[t], motion.tags[t]->pose_at(t_s)});
    for (size_t ai = 0; ai < ants.size(); ++ai) {
      const AntennaSpec& spec = scenario.antennas[ants[ai]];
      const Pose mount = motion.antennas[ants[ai]]->pose_at(t_s);
      view.antennas.push_back({spec.reader.name, mount});
      const Endpoint antenna{phase_centre_pose(spec.reader, mount), spec.reader.pattern, spec.reader.polarization};
      const double f = spec.reader.frequencies_hz[hop_index_at(spec.reader, t_s)];
      for (size_t ti = 0; ti < present.size(); ++ti) {
        const TagSpec& tag = scenario.tags[present[ti]];
        const Endpoint end{view.tags[ti].pose, tag.tag.pattern, tag.tag.polarization};
        if (!((antenna.pose.position - end.pose.position).norm() >= kMinLinkDistance_m))
          throw InputError(view.title + ": tag '" + tag.tag.name + "' is at antenna '" + spec.reader.name + "' at t = " +
                           num(t_s) + " s");
        view.links.push_back({ai, ti, f, antenna.pose.position, end.pose.position, channel->paths(antenna, end, f)});
      }
    }
    view.title += " at t = " + num(t_s) + " s";
  }
  view.level = channel->name();
  view.scene = scene.get();
  io::write_view_html(o.output, view);
  std::printf("rfidray view: %zu links, %zu paths (%s), %zu triangles -> %s\n", view.links.size(),
              io::view_path_count(view), view.level.c_str(), scene ? scene->triangle_count() : size_t{0},
              o.output.c_str());
  return 0;
}

}  // namespace

std::function<int()> setup_view(CLI::App& app) {
  auto o = std::make_shared<ViewOptions>();
  CLI::App* cmd = app.add_subcommand("view", "Write a self-contained HTML 3-D view of a scene and its traced paths");
  cmd->footer(
      "The scene mesh coloured by radio material (legend), antennas with boresight arrows, tags, and every path\n"
      "of every antenna-tag link (los, blocked dashed, reflections) coloured by its power relative to the\n"
      "strongest path of its link; hover a path for its length, material and coefficient; drag to orbit.\n"
      "three.js comes from Debian's libjs-three and is inlined: the page needs no network.\n"
      "With a SCENARIO or --world: its antennas and the tags present at --time (default 0) or --tick, with their\n"
      "patterns and polarizations (--antenna/--tag NAME pick some). With --scene: --antenna X,Y,Z and --tag X,Y,Z\n"
      "(repeatable, every antenna with every tag; isotropic, linear polarization along z, as `rfidray link`).");
  cmd->add_option("SCENARIO", o->scenario, "Scenario YAML file (or --scene / --world)");
  cmd->add_option("--scene", o->scene, "OBJ scene file(s) instead of a scenario");
  add_world_options(*cmd, o->world);
  cmd->add_option("--default-material", o->default_material, "radio material for unknown usemtl names (--scene, --world)");
  cmd->add_option("--antenna", o->antennas, "--scene: antenna position X,Y,Z; scenario/world: an antenna's name");
  cmd->add_option("--tag", o->tags, "--scene: tag position X,Y,Z; scenario/world: a tag's name");
  cmd->add_option("--time", o->time_s, "scenario time (s) of the poses shown (default 0)");
  cmd->add_option("--tick", o->tick, "read tick of the first antenna shown (t = N / its update rate)");
  add_channel_option_with_level_alias(*cmd, o->level, "los | los+blocked | single-bounce | ideal | auto (default: the "
                                                     "scenario's channel when traced, else single-bounce)");
  cmd->add_option("--frequency", o->frequency_hz, "carrier (Hz) with --scene (a scenario's antennas give theirs)");
  cmd->add_option("-o,--output", o->output, "HTML file to write")->capture_default_str();
  return [o] { return run_view(*o); };
}

}  // namespace rfidray::cli
