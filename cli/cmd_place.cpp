// `rfidray place`: choose K antenna poses among candidates to read the most tags (planning/placement.h) or to minimise
// the worst localization bound (planning/placement_bound.h), from the coverage of every candidate over the cells
// (planning/coverage_map.h, sharded over MPI ranks); writes the choice, an objective-vs-K curve, a map of the chosen
// placement, the chosen placement's value per cell, and a scenario with the chosen antennas that `simulate` runs.
#include <yaml-cpp/yaml.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>

#include "cli/commands.h"
#include "cli/planning.h"
#include "core/error.h"
#include "core/memory_budget.h"
#include "core/units.h"
#include "io/atomic_file.h"
#include "io/candidates_yaml.h"
#include "io/checked_yaml.h"
#include "io/map_plot.h"
#include "planning/placement.h"
#include "planning/placement_bound.h"
#include "io/plot.h"
#include "parallel/ranks.h"

namespace rfidray::cli {
namespace {

namespace fs = std::filesystem;

struct PlaceOptions {
  PlanningOptions plan;
  std::string candidates;
  std::string objective = "coverage";  // coverage | worst-bound
  int k = 3;
  double min_probability = 0.9;
  double exact_limit = 1e6;
};

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

// A bound (m) for files and messages: empty (or `none`) when it does not exist — never "inf" or "nan".
std::string bound_text(double v, const char* none = "") { return std::isfinite(v) ? fmt("%.6f", v) : none; }

// Roll, pitch, yaw (deg) of an orientation, R = Rz(yaw)·Ry(pitch)·Rx(roll).
Vec3 rpy_deg(const Quat& q) {
  const Eigen::Matrix3d r = q.toRotationMatrix();
  const double yaw = std::atan2(r(1, 0), r(0, 0)), pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0)),
               roll = std::atan2(r(2, 1), r(2, 2));
  auto deg = [](double rad) {
    const double d = rad * 180.0 / kPi;
    return std::abs(d) < 5e-10 ? 0.0 : d;  // no "-0"
  };
  return Vec3(deg(roll), deg(pitch), deg(yaw));
}

// The scenario file with its antennas replaced by the chosen mounts (each a copy of its template antenna's keys
// without its place: a world pose, or `robot` + `mount` for a robot mount), mesh and antenna-file paths rewritten
// relative to the output directory.
void write_placed_scenario(const fs::path& out, const std::string& scenario_file,
                           const std::vector<size_t>& template_index, const std::vector<io::CandidateMount>& chosen,
                           const std::vector<std::string>& robot_of) {
  YAML::Node root = io::load_yaml_file(scenario_file, "scenario file");
  const fs::path base = fs::absolute(fs::path(scenario_file)).parent_path();
  const fs::path out_dir = fs::absolute(out).parent_path();
  auto rebase = [&](YAML::Node n) {
    if (!n || !n.IsScalar()) return;
    const fs::path p(n.Scalar());
    n = fs::relative(fs::weakly_canonical(p.is_absolute() ? p : base / p), out_dir).string();
  };
  if (root["scene"] && root["scene"]["meshes"])
    for (YAML::Node m : root["scene"]["meshes"]) rebase(m["file"]);
  const YAML::Node originals = YAML::Clone(root["antennas"]);
  YAML::Node antennas(YAML::NodeType::Sequence);
  for (size_t i = 0; i < chosen.size(); ++i) {
    const io::CandidateMount& c = chosen[i];
    YAML::Node a = YAML::Clone(originals[template_index[i]]);
    for (const char* k : {"robot", "mount", "waypoints", "speed_m_s", "mast", "position", "rpy_deg", "yaw_deg",
                          "quaternion", "start_s"})
      a.remove(k);
    a["name"] = c.name;
    rebase(a["antenna_file"]);
    YAML::Node pos(YAML::NodeType::Sequence), rpy(YAML::NodeType::Sequence);
    pos.SetStyle(YAML::EmitterStyle::Flow);
    rpy.SetStyle(YAML::EmitterStyle::Flow);
    const Vec3 r = rpy_deg(c.pose.orientation);
    // 10 significant digits: 1.68, not 1.6799999999999999; −90, not −89.999999999999986.
    for (int k = 0; k < 3; ++k) pos.push_back(fmt("%.10g", c.pose.position[k] + 0.0)), rpy.push_back(fmt("%.10g", r[k] + 0.0));
    if (c.on_robot) {
      YAML::Node mount(YAML::NodeType::Map);
      mount.SetStyle(YAML::EmitterStyle::Flow);
      mount["position"] = pos;
      mount["rpy_deg"] = rpy;
      a["robot"] = robot_of[i];
      a["mount"] = mount;
    } else {
      a["position"] = pos;
      a["rpy_deg"] = rpy;
    }
    antennas.push_back(a);
  }
  root["antennas"] = antennas;
  YAML::Emitter e;
  e.SetDoublePrecision(10);
  e << root;
  io::write_file_atomic(out, [&](std::ostream& s) {
    s << "# Written by `rfidray place` from " << scenario_file << ": its antennas replaced by the chosen mounts.\n"
      << e.c_str() << "\n";
  }, "placed scenario");
}

// The scenario antenna a candidate copies, and for a robot mount its robot (InputError naming the file).
struct Template {
  size_t antenna = 0;
  std::string robot;
};

Template resolve_template(const Scenario& sc, const std::string& source, const std::string& file,
                          const io::CandidateFile& cand, const io::CandidateMount& m) {
  auto named = [&](const std::string& name, const std::string& field) {
    for (size_t a = 0; a < sc.antennas.size(); ++a)
      if (sc.antennas[a].reader.name == name) return a;
    throw InputError(file + ": field '" + field + "': no antenna '" + name + "' in " + source);
  };
  Template t;
  if (m.on_robot) {
    std::string known;
    for (const RobotSpec& r : sc.robots) known += (known.empty() ? "" : ", ") + r.name;
    if (m.robot.empty()) {
      if (sc.robots.size() != 1)
        throw InputError(file + ": robot mount '" + m.name + "': give robot: NAME (" + source + " has " +
                         (sc.robots.empty() ? std::string("no robot") : "robots " + known) + ")");
      t.robot = sc.robots.front().name;
    } else {
      t.robot = m.robot;
      if (std::none_of(sc.robots.begin(), sc.robots.end(), [&](const RobotSpec& r) { return r.name == m.robot; }))
        throw InputError(file + ": robot mount '" + m.name + "': no robot '" + m.robot + "' in " + source +
                         " (robots: " + (known.empty() ? "none" : known) + ")");
    }
    if (!m.template_antenna.empty()) return t.antenna = named(m.template_antenna, "robot_mounts: template"), t;
    for (size_t a = 0; a < sc.antennas.size(); ++a)
      if (sc.antennas[a].motion.kind == MotionSpec::Kind::kRobot && sc.antennas[a].motion.robot == t.robot)
        return t.antenna = a, t;
  }
  if (!cand.template_antenna.empty()) return t.antenna = named(cand.template_antenna, "template"), t;
  // The first fixed antenna, else the first.
  for (size_t a = 0; a < sc.antennas.size(); ++a)
    if (sc.antennas[a].motion.kind == MotionSpec::Kind::kFixed && !sc.antennas[a].motion.mast) return t.antenna = a, t;
  return t;
}

int run_place(const PlaceOptions& o) {
  const parallel::Ranks& ranks = parallel::Ranks::world();
  if (o.candidates.empty()) throw InputError("option --candidates: a candidates YAML file is required");
  if (!(o.min_probability > 0.0 && o.min_probability <= 1.0))
    throw InputError("option --min-probability: must be in (0, 1]");
  if (o.objective != "coverage" && o.objective != "worst-bound")
    throw InputError("option --objective: expected coverage or worst-bound (got '" + clip(o.objective) + "')");
  const bool by_bound = o.objective == "worst-bound";
  Planning p = prepare_planning(o.plan);
  const io::CandidateFile cand = io::load_candidates(o.candidates);
  if (o.k < 1 || static_cast<size_t>(o.k) > cand.mounts.size())
    throw InputError("option -k: must be in [1, " + std::to_string(cand.mounts.size()) + "] (the number of candidates)");
  if (p.scenario.antennas.empty())
    throw InputError(p.source + ": no antenna to take the candidates' radio keys from (add one as a template)");
  std::vector<size_t> template_of, indices;
  std::vector<std::string> robot_of;
  bool any_on_robot = false;
  for (const io::CandidateMount& m : cand.mounts) {
    const Template t = resolve_template(p.scenario, p.source, o.candidates, cand, m);
    AntennaSpec a = p.scenario.antennas[t.antenna];
    a.reader.name = m.name;
    a.motion = MotionSpec{};
    a.motion.pose = m.pose;
    if (m.on_robot) {
      // Over the robot's whole pass, reading from when the template antenna starts to.
      a.motion.kind = MotionSpec::Kind::kRobot;
      a.motion.robot = t.robot;
      any_on_robot = true;
    } else {
      a.start_s = 0.0;
    }
    template_of.push_back(t.antenna);
    robot_of.push_back(t.robot);
    indices.push_back(p.scenario.antennas.size());
    p.scenario.antennas.push_back(std::move(a));
  }
  if (by_bound && !any_on_robot)
    throw InputError("option --objective worst-bound: " + o.candidates +
                     " has no robot_mounts; a fixed antenna fixes no position from its phase (one offset per carrier), "
                     "so only antennas that move over a pass have a localization bound");
  p.motion = build_motion(p.scenario);
  const size_t n_c = cand.mounts.size(), n_t = p.cells.size();
  // The passes' informations: for the objective, and for the joint bound of the choice whenever some candidate
  // moves. Per candidate and cell in flight: 4 values (+ 6 of information), three copies (local, gathered,
  // unpacked).
  const bool with_info = by_bound || any_on_robot;
  check_memory_estimate(double(n_c) * double(n_t) * (with_info ? 10.0 : 4.0) * 8.0 * 3.0,
                        "place: " + std::to_string(n_c) + " candidates x " + std::to_string(n_t) + " cells",
                        with_info ? "240 bytes per candidate and cell" : "96 bytes per candidate and cell");
  const fs::path dir(o.plan.output_dir);
  if (ranks.root()) make_output_dir(o.plan.output_dir);
  const std::vector<planning::CoverageValues> values = sharded_coverage(p, indices, o.plan, "place", with_info);
  if (!ranks.root()) return 0;

  const size_t k = static_cast<size_t>(o.k);
  planning::CoverSets sets(n_c, n_t);
  for (size_t c = 0; c < n_c; ++c)
    for (size_t t = 0; t < n_t; ++t)
      if (values[c].read_probability[t] >= o.min_probability) sets.set(c, t);
  std::optional<planning::InformationSets> info;
  if (with_info) {
    info.emplace(n_c, n_t, !o.plan.three_d);
    for (size_t c = 0; c < n_c; ++c) std::copy(values[c].information.begin(), values[c].information.end(), info->at(c, 0));
  }

  // The choice, and the curve: greedy alone and the final choice for every K' ≤ K.
  std::vector<size_t> chosen;
  planning::Placement best_cover;
  planning::BoundPlacement best_bound;
  std::vector<planning::BoundScore> refined_bound;
  std::vector<size_t> refined_cover;
  if (by_bound) {
    best_bound = planning::place_min_worst_bound(*info, k, o.exact_limit);
    for (size_t kk = 1; kk <= k; ++kk)
      refined_bound.push_back(kk == k ? best_bound.score : planning::place_min_worst_bound(*info, kk, o.exact_limit).score);
    chosen = best_bound.chosen;
  } else {
    best_cover = planning::place_antennas(sets, k, o.exact_limit);
    for (size_t kk = 1; kk <= k; ++kk)
      refined_cover.push_back(kk == k ? best_cover.covered : planning::place_antennas(sets, kk, o.exact_limit).covered);
    chosen = best_cover.chosen;
  }
  const bool exact = by_bound ? best_bound.exact : best_cover.exact;

  // The chosen placement per cell: the best read probability of its antennas, their joint bound.
  std::vector<double> best_p(n_t, 0.0);
  for (size_t c : chosen)
    for (size_t t = 0; t < n_t; ++t)
      if (std::isfinite(values[c].read_probability[t])) best_p[t] = std::max(best_p[t], values[c].read_probability[t]);
  std::vector<double> joint_bound(n_t, std::numeric_limits<double>::quiet_NaN());
  if (info) joint_bound = info->bounds_m(chosen);
  const bool has_bound = std::any_of(joint_bound.begin(), joint_bound.end(), [](double b) { return std::isfinite(b); });

  std::vector<io::CandidateMount> mounts;
  std::vector<size_t> chosen_templates;
  std::vector<std::string> chosen_robots;
  for (size_t c : chosen) mounts.push_back(cand.mounts[c]), chosen_templates.push_back(template_of[c]),
                          chosen_robots.push_back(robot_of[c]);
  io::write_file_atomic(dir / "placement.csv", [&](std::ostream& s) {
    s << "rank,candidate,name,x,y,z,roll_deg,pitch_deg,yaw_deg,tags_read,tags_localized,worst_bound_m,mounted_on\n";
    for (size_t i = 0; i < chosen.size(); ++i) {
      const size_t c = chosen[i];
      const io::CandidateMount& m = cand.mounts[c];
      const Vec3 r = rpy_deg(m.pose.orientation);
      size_t alone = 0, localized = 0;
      double worst = -1.0;
      for (size_t t = 0; t < n_t; ++t) {
        alone += sets.covers(c, t);
        const double b = values[c].localization_bound_m[t];
        if (std::isfinite(b)) ++localized, worst = std::max(worst, b);
      }
      s << i + 1 << ',' << c << ',' << m.name << ',' << fmt("%.4f", m.pose.position.x()) << ','
        << fmt("%.4f", m.pose.position.y()) << ',' << fmt("%.4f", m.pose.position.z()) << ',' << fmt("%.3f", r.x())
        << ',' << fmt("%.3f", r.y()) << ',' << fmt("%.3f", r.z()) << ',' << alone << ',' << localized << ','
        << (localized ? bound_text(worst) : "") << ',' << (m.on_robot ? robot_of[c] : "world") << '\n';
    }
  }, "placement CSV");
  io::write_file_atomic(dir / "coverage_vs_k.csv", [&](std::ostream& s) {
    if (by_bound) {
      s << "k,greedy_localized,greedy_worst_bound_m,localized,worst_bound_m,cells\n";
      for (size_t i = 0; i < k; ++i)
        s << i + 1 << ',' << best_bound.greedy_curve[i].localized << ',' << bound_text(best_bound.greedy_curve[i].worst_m)
          << ',' << refined_bound[i].localized << ',' << bound_text(refined_bound[i].worst_m) << ',' << n_t << '\n';
    } else {
      s << "k,greedy_covered,refined_covered,tags\n";
      for (size_t i = 0; i < k; ++i)
        s << i + 1 << ',' << best_cover.greedy_curve[i] << ',' << refined_cover[i] << ',' << n_t << '\n';
    }
  }, "coverage-vs-K CSV");
  io::write_file_atomic(dir / "placement_cells.csv", [&](std::ostream& s) {
    s << "x,y,z,read_probability,localization_bound_m\n";
    for (size_t t = 0; t < n_t; ++t) {
      const Vec3& q = p.cells.poses[t].position;
      s << fmt("%.4f", q.x()) << ',' << fmt("%.4f", q.y()) << ',' << fmt("%.4f", q.z()) << ',' << fmt("%.6f", best_p[t])
        << ',' << bound_text(joint_bound[t]) << '\n';
    }
  }, "placement cells CSV");

  std::vector<std::string> pngs;
  if (!o.plan.no_png) {
    const std::string chosen_label = exact ? "chosen (optimal: every K-subset tried)" : "chosen (greedy + swaps)";
    io::Panel panel;
    if (by_bound) {
      // Worst bound vs K, each point labelled with the cells it localizes (the first criterion).
      io::Series g{"greedy", {}, {}, "linespoints"}, r{chosen_label, {}, {}, "linespoints"};
      for (size_t i = 0; i < k; ++i) {
        const auto add = [&](io::Series& s, const planning::BoundScore& b) {
          if (!std::isfinite(b.worst_m)) return;
          s.x.push_back(double(i + 1)), s.y.push_back(b.worst_m);
          s.labels.push_back(std::to_string(b.localized) + "/" + std::to_string(n_t));
        };
        add(g, best_bound.greedy_curve[i]);
        add(r, refined_bound[i]);
      }
      panel = io::Panel{"worst localization bound by K antennas (" + std::to_string(n_c) +
                            " candidates; labels: cells localized)",
                        "K (antennas)", "worst bound (m, Cramer-Rao RMS)", {g, r}};
      panel.log_y = true;
    } else {
      io::Series g{"greedy", {}, {}, "linespoints"}, r{chosen_label, {}, {}, "linespoints"};
      for (size_t i = 0; i < k; ++i) {
        g.x.push_back(double(i + 1)), g.y.push_back(100.0 * double(best_cover.greedy_curve[i]) / double(n_t));
        r.x.push_back(double(i + 1)), r.y.push_back(100.0 * double(refined_cover[i]) / double(n_t));
      }
      panel = io::Panel{"tags read with p >= " + fmt("%.2f", o.min_probability) + " by K antennas (" +
                            std::to_string(n_c) + " candidates, " + std::to_string(n_t) + " cells)",
                        "K (antennas)", "cells covered (%)", {g, r}};
    }
    io::write_png(dir / "coverage_vs_k.png", {panel}, 900, 420);
    pngs.push_back((dir / "coverage_vs_k.png").string());
    if (p.grid || o.plan.box.empty()) {
      std::vector<size_t> chosen_idx;
      for (size_t c : chosen) chosen_idx.push_back(indices[c]);
      io::FloorMap m;
      if (by_bound) {
        m = floor_map(p, chosen_idx, joint_bound,
                      std::to_string(k) + " antennas placed: joint localization bound (" +
                          std::to_string(best_bound.score.localized) + " of " + std::to_string(n_t) +
                          " cells localized, worst " + bound_text(best_bound.score.worst_m, "none") + " m)",
                      "localization bound (m, Cramer-Rao RMS)", o.plan.view);
        m.reversed_palette = true;
        m.log_scale = true;
      } else {
        m = floor_map(p, chosen_idx, best_p,
                      std::to_string(k) + " antennas placed: best read probability (" +
                          std::to_string(best_cover.covered) + " of " + std::to_string(n_t) + " cells >= " +
                          fmt("%.2f", o.min_probability) + ")",
                      "read probability (best antenna)", o.plan.view);
        m.range = std::make_pair(0.0, 1.0);
      }
      io::write_map_png(dir / "placement.png", m);
      pngs.push_back((dir / "placement.png").string());
    }
  }
  if (o.plan.world.file.empty())
    write_placed_scenario(dir / "placed.yaml", o.plan.scenario, chosen_templates, mounts, chosen_robots);
  if (o.plan.quiet) return 0;
  std::printf("rfidray place %s: %zu candidates, %zu cells, K = %zu, objective %s; channel %s; %d rank%s\n",
              p.source.c_str(), n_c, n_t, k,
              by_bound ? "worst-bound (min-max: not submodular, no 1-1/e guarantee)"
                       : ("coverage (p >= " + fmt("%.2f", o.min_probability) + ")").c_str(),
              p.channel->name().c_str(), ranks.size(), ranks.size() == 1 ? "" : "s");
  if (by_bound) {
    auto score = [&](const planning::BoundScore& b) {
      return std::to_string(b.localized) + " of " + std::to_string(n_t) + " cells localized, worst bound " +
             bound_text(b.worst_m, "none") + (std::isfinite(b.worst_m) ? " m" : "");
    };
    std::printf("  greedy: %s; after %zu swap%s: %s", score(best_bound.greedy_curve.back()).c_str(), best_bound.swaps,
                best_bound.swaps == 1 ? "" : "s", score(best_bound.heuristic).c_str());
    if (exact)
      std::printf("; exhaustive over all %.0f subsets: %s (optimal)", planning::subset_count(n_c, k),
                  score(best_bound.score).c_str());
    std::printf("\n");
  } else {
    std::printf("  greedy: %zu cells; after %zu swap%s: %zu cells", best_cover.greedy_curve.back(), best_cover.swaps,
                best_cover.swaps == 1 ? "" : "s", best_cover.heuristic_covered);
    if (exact)
      std::printf("; exhaustive over all %.0f subsets: %zu cells (optimal)", planning::subset_count(n_c, k), best_cover.covered);
    std::printf(" = %.1f %%\n", 100.0 * double(best_cover.covered) / double(n_t));
  }
  for (size_t c : chosen) {
    const io::CandidateMount& m = cand.mounts[c];
    const Vec3 r = rpy_deg(m.pose.orientation);
    if (m.on_robot)
      std::printf("  %s on robot %s at (%.2f, %.2f, %.2f) in its frame, rpy (%.0f, %.0f, %.0f) deg\n", m.name.c_str(),
                  robot_of[c].c_str(), m.pose.position.x(), m.pose.position.y(), m.pose.position.z(), r.x(), r.y(), r.z());
    else
      std::printf("  %s at (%.2f, %.2f, %.2f), rpy (%.0f, %.0f, %.0f) deg\n", m.name.c_str(), m.pose.position.x(),
                  m.pose.position.y(), m.pose.position.z(), r.x(), r.y(), r.z());
  }
  if (has_bound && !by_bound) std::printf("  (the chosen antennas' joint localization bound per cell in placement_cells.csv)\n");
  std::printf("  -> %s, %s, %s%s\n", (dir / "placement.csv").string().c_str(), (dir / "coverage_vs_k.csv").string().c_str(),
              (dir / "placement_cells.csv").string().c_str(),
              o.plan.world.file.empty() ? (", " + (dir / "placed.yaml").string()).c_str() : "");
  for (const std::string& png : pngs) std::printf("  -> %s\n", png.c_str());
  return 0;
}

}  // namespace

std::function<int()> setup_place(CLI::App& app) {
  auto o = std::make_shared<PlaceOptions>();
  CLI::App* cmd = app.add_subcommand("place", "Choose K antenna poses among candidates to read the most tags");
  cmd->footer(
      "Every candidate (a copy of a template antenna at a mount of --candidates, io/candidates_yaml.h: fixed\n"
      "mounts, grids, or robot_mounts evaluated over the robot's whole pass) is mapped over the cells as\n"
      "`rfidray coverage` does. --objective coverage (default): a cell counts as covered when some chosen antenna\n"
      "reads it with probability >= --min-probability; greedy (within 1 - 1/e of optimal), then swaps while they\n"
      "cover more. --objective worst-bound: the chosen antennas' Cramer-Rao informations add; first the most cells\n"
      "with a finite bound, then the smallest worst bound (min-max, not submodular: greedy + swaps carry no\n"
      "guarantee). Either way, when C(candidates, K) <= --exact-limit, every K-subset is tried (optimal).\n"
      "Output in DIR: placement.csv, coverage_vs_k.csv/.png, placement_cells.csv (the choice per cell),\n"
      "placement.png, placed.yaml (the scenario with the chosen antennas: `rfidray simulate DIR/placed.yaml`).\n"
      "Scale out: mpirun -n N rfidray place ...");
  add_planning_options(*cmd, o->plan);
  cmd->add_option("--candidates", o->candidates, "candidate mounts (YAML: template, mounts, grids, robot_mounts)")->required();
  cmd->add_option("-k,--count", o->k, "number of antennas to place");
  cmd->add_option("--objective", o->objective,
                  "coverage: the most cells read with p >= --min-probability; worst-bound: the most cells localized, "
                  "then the smallest worst localization bound (robot_mounts)");
  cmd->add_option("--min-probability", o->min_probability,
                  "objective coverage: a cell is covered when read with at least this probability");
  cmd->add_option("--exact-limit", o->exact_limit,
                  "try every K-subset when there are at most this many (then the choice is optimal; 0: never)");
  cmd->add_option("-o,--output", o->plan.output_dir, "output directory (default out/place)");
  o->plan.output_dir = "out/place";
  return [o] { return run_place(*o); };
}

}  // namespace rfidray::cli
