// `rfidray place`: choose K antenna poses among candidates to read the most tags (io/placement.h), from the
// coverage of every candidate over the cells (io/coverage_map.h, sharded over MPI ranks); writes the choice, a
// coverage-vs-K curve, a map of the chosen placement, and a scenario with the chosen antennas that `simulate` runs.
#include <yaml-cpp/yaml.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>

#include "cli/commands.h"
#include "cli/planning.h"
#include "core/error.h"
#include "core/units.h"
#include "io/atomic_file.h"
#include "io/candidates_yaml.h"
#include "io/checked_yaml.h"
#include "io/map_plot.h"
#include "io/placement.h"
#include "io/plot.h"
#include "parallel/ranks.h"

namespace rfidray::cli {
namespace {

namespace fs = std::filesystem;

struct PlaceOptions {
  PlanningOptions plan;
  std::string candidates;
  int k = 3;
  double min_probability = 0.9;
  double exact_limit = 1e6;
};

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

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

// The scenario file with its antennas replaced by the chosen mounts (each a copy of the template antenna's keys
// without its place), mesh and antenna-file paths rewritten relative to the output directory.
void write_placed_scenario(const fs::path& out, const std::string& scenario_file, size_t template_index,
                           const std::vector<io::CandidateMount>& chosen) {
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
  const YAML::Node tmpl = root["antennas"][template_index];
  YAML::Node antennas(YAML::NodeType::Sequence);
  for (const io::CandidateMount& c : chosen) {
    YAML::Node a = YAML::Clone(tmpl);
    for (const char* k : {"robot", "mount", "waypoints", "speed_m_s", "mast", "position", "rpy_deg", "yaw_deg",
                          "quaternion", "start_s"})
      a.remove(k);
    a["name"] = c.name;
    rebase(a["antenna_file"]);
    YAML::Node pos(YAML::NodeType::Sequence), rpy(YAML::NodeType::Sequence);
    pos.SetStyle(YAML::EmitterStyle::Flow);
    rpy.SetStyle(YAML::EmitterStyle::Flow);
    const Vec3 r = rpy_deg(c.pose.orientation);
    for (int k = 0; k < 3; ++k) pos.push_back(c.pose.position[k]), rpy.push_back(r[k]);
    a["position"] = pos;
    a["rpy_deg"] = rpy;
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

int run_place(const PlaceOptions& o) {
  const parallel::Ranks& ranks = parallel::Ranks::world();
  if (o.candidates.empty()) throw InputError("option --candidates: a candidates YAML file is required");
  if (!(o.min_probability > 0.0 && o.min_probability <= 1.0))
    throw InputError("option --min-probability: must be in (0, 1]");
  Planning p = prepare_planning(o.plan);
  const io::CandidateFile cand = io::load_candidates(o.candidates);
  if (o.k < 1 || static_cast<size_t>(o.k) > cand.mounts.size())
    throw InputError("option -k: must be in [1, " + std::to_string(cand.mounts.size()) + "] (the number of candidates)");
  // The template: named, else the first fixed antenna, else the first.
  size_t tmpl = p.scenario.antennas.size();
  for (size_t a = 0; a < p.scenario.antennas.size(); ++a) {
    const AntennaSpec& s = p.scenario.antennas[a];
    if (cand.template_antenna.empty() ? s.motion.kind == MotionSpec::Kind::kFixed && !s.motion.mast
                                      : s.reader.name == cand.template_antenna) {
      tmpl = a;
      break;
    }
  }
  if (tmpl == p.scenario.antennas.size()) {
    if (!cand.template_antenna.empty())
      throw InputError(o.candidates + ": field 'template': no antenna '" + cand.template_antenna + "' in " + p.source);
    tmpl = 0;
  }
  const size_t first = p.scenario.antennas.size();
  std::vector<size_t> indices;
  for (const io::CandidateMount& m : cand.mounts) {
    AntennaSpec a = p.scenario.antennas[tmpl];
    a.reader.name = m.name;
    a.motion = MotionSpec{};
    a.motion.pose = m.pose;
    a.start_s = 0.0;
    indices.push_back(p.scenario.antennas.size());
    p.scenario.antennas.push_back(std::move(a));
  }
  p.motion = build_motion(p.scenario);
  const fs::path dir(o.plan.output_dir);
  if (ranks.root()) make_output_dir(o.plan.output_dir);
  const std::vector<io::CoverageValues> values = sharded_coverage(p, indices, o.plan, "place");
  if (!ranks.root()) return 0;

  const size_t n_c = cand.mounts.size(), n_t = p.cells.size();
  io::CoverSets sets(n_c, n_t);
  for (size_t c = 0; c < n_c; ++c)
    for (size_t t = 0; t < n_t; ++t)
      if (values[c].read_probability[t] >= o.min_probability) sets.set(c, t);
  const size_t k = static_cast<size_t>(o.k);
  const io::Placement best = io::place_antennas(sets, k, o.exact_limit);
  // The curve: greedy alone and greedy + swaps for every K' ≤ K.
  io::Series greedy{"greedy", {}, {}, "linespoints"}, refined{"chosen (greedy + swaps, exact when few subsets)", {}, {}, "linespoints"};
  for (size_t kk = 1; kk <= k; ++kk) {
    const io::Placement pk = kk == k ? best : io::place_antennas(sets, kk, o.exact_limit);
    greedy.x.push_back(double(kk)), greedy.y.push_back(100.0 * double(best.greedy_curve[kk - 1]) / double(n_t));
    refined.x.push_back(double(kk)), refined.y.push_back(100.0 * double(pk.covered) / double(n_t));
  }

  std::vector<io::CandidateMount> chosen;
  for (size_t c : best.chosen) chosen.push_back(cand.mounts[c]);
  io::write_file_atomic(dir / "placement.csv", [&](std::ostream& s) {
    s << "rank,candidate,name,x,y,z,roll_deg,pitch_deg,yaw_deg,tags_read\n";
    for (size_t i = 0; i < best.chosen.size(); ++i) {
      const io::CandidateMount& m = cand.mounts[best.chosen[i]];
      const Vec3 r = rpy_deg(m.pose.orientation);
      size_t alone = 0;
      for (size_t t = 0; t < n_t; ++t) alone += sets.covers(best.chosen[i], t);
      s << i + 1 << ',' << best.chosen[i] << ',' << m.name << ',' << fmt("%.4f", m.pose.position.x()) << ','
        << fmt("%.4f", m.pose.position.y()) << ',' << fmt("%.4f", m.pose.position.z()) << ',' << fmt("%.3f", r.x())
        << ',' << fmt("%.3f", r.y()) << ',' << fmt("%.3f", r.z()) << ',' << alone << '\n';
    }
  }, "placement CSV");
  io::write_file_atomic(dir / "coverage_vs_k.csv", [&](std::ostream& s) {
    s << "k,greedy_covered,refined_covered,tags\n";
    for (size_t i = 0; i < k; ++i)
      s << i + 1 << ',' << best.greedy_curve[i] << ',' << fmt("%.0f", refined.y[i] * double(n_t) / 100.0) << ',' << n_t
        << '\n';
  }, "coverage-vs-K CSV");
  std::vector<std::string> pngs;
  if (!o.plan.no_png) {
    io::Panel panel{"tags read with p >= " + fmt("%.2f", o.min_probability) + " by K antennas (" +
                        std::to_string(n_c) + " candidates, " + std::to_string(n_t) + " cells)",
                    "K (antennas)", "cells covered (%)", {greedy, refined}};
    io::write_png(dir / "coverage_vs_k.png", {panel}, 900, 420);
    pngs.push_back((dir / "coverage_vs_k.png").string());
    if (p.grid || o.plan.box.empty()) {
      // Best read probability over the chosen antennas.
      std::vector<double> best_p(n_t, 0.0);
      for (size_t c : best.chosen)
        for (size_t t = 0; t < n_t; ++t)
          if (std::isfinite(values[c].read_probability[t])) best_p[t] = std::max(best_p[t], values[c].read_probability[t]);
      std::vector<size_t> chosen_idx;
      for (size_t c : best.chosen) chosen_idx.push_back(indices[c]);
      io::FloorMap m = floor_map(p, chosen_idx, best_p,
                                 std::to_string(k) + " antennas placed: best read probability (" +
                                     std::to_string(best.covered) + " of " + std::to_string(n_t) + " cells >= " +
                                     fmt("%.2f", o.min_probability) + ")",
                                 "read probability (best antenna)", o.plan.view);
      m.range = std::make_pair(0.0, 1.0);
      io::write_map_png(dir / "placement.png", m);
      pngs.push_back((dir / "placement.png").string());
    }
  }
  if (o.plan.world.file.empty())
    write_placed_scenario(dir / "placed.yaml", o.plan.scenario, tmpl, chosen);
  (void)first;
  if (o.plan.quiet) return 0;
  std::printf("rfidray place %s: %zu candidates, %zu cells, K = %zu, p >= %.2f; channel %s; %d rank%s\n",
              p.source.c_str(), n_c, n_t, k, o.min_probability, p.channel->name().c_str(), ranks.size(),
              ranks.size() == 1 ? "" : "s");
  std::printf("  greedy: %zu cells; after %zu swap%s: %zu cells", best.greedy_curve.back(), best.swaps,
              best.swaps == 1 ? "" : "s", best.heuristic_covered);
  if (best.exact)
    std::printf("; exhaustive over all %.0f subsets: %zu cells (optimal)", io::subset_count(n_c, k), best.covered);
  std::printf(" = %.1f %%\n", 100.0 * double(best.covered) / double(n_t));
  for (size_t c : best.chosen) {
    const Vec3 r = rpy_deg(cand.mounts[c].pose.orientation);
    std::printf("  %s at (%.2f, %.2f, %.2f), rpy (%.0f, %.0f, %.0f) deg\n", cand.mounts[c].name.c_str(),
                cand.mounts[c].pose.position.x(), cand.mounts[c].pose.position.y(), cand.mounts[c].pose.position.z(),
                r.x(), r.y(), r.z());
  }
  std::printf("  -> %s, %s%s\n", (dir / "placement.csv").string().c_str(), (dir / "coverage_vs_k.csv").string().c_str(),
              o.plan.world.file.empty() ? (", " + (dir / "placed.yaml").string()).c_str() : "");
  for (const std::string& png : pngs) std::printf("  -> %s\n", png.c_str());
  return 0;
}

}  // namespace

std::function<int()> setup_place(CLI::App& app) {
  auto o = std::make_shared<PlaceOptions>();
  CLI::App* cmd = app.add_subcommand("place", "Choose K antenna poses among candidates to read the most tags");
  cmd->footer(
      "Every candidate (a copy of the template antenna at a mount of --candidates, io/candidates_yaml.h) is\n"
      "mapped over the cells as `rfidray coverage` does; a cell counts as covered when some chosen antenna reads\n"
      "it with probability >= --min-probability. Greedy selection (within 1 - 1/e of optimal), then swaps while\n"
      "they cover more; when C(candidates, K) <= --exact-limit, every K-subset (optimal). Output in DIR: placement.csv, coverage_vs_k.csv/.png, placement.png (best read\n"
      "probability of the chosen antennas), placed.yaml (the scenario with the chosen antennas: `rfidray\n"
      "simulate DIR/placed.yaml`). Scale out: mpirun -n N rfidray place ...");
  add_planning_options(*cmd, o->plan);
  cmd->add_option("--candidates", o->candidates, "candidate mounts (YAML: template, mounts, grids)")->required();
  cmd->add_option("-k,--count", o->k, "number of antennas to place");
  cmd->add_option("--min-probability", o->min_probability, "a cell is covered when read with at least this probability");
  cmd->add_option("--exact-limit", o->exact_limit,
                  "try every K-subset when there are at most this many (then the choice is optimal; 0: never)");
  cmd->add_option("-o,--output", o->plan.output_dir, "output directory (default out/place)");
  o->plan.output_dir = "out/place";
  return [o] { return run_place(*o); };
}

}  // namespace rfidray::cli
