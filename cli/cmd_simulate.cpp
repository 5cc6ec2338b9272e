// rfidray simulate SCENARIO: run a scenario, write one readings CSV per antenna and the tags' ground truth.
#include <omp.h>

#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdint>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>

#include "io/atomic_file.h"
#include "raytrace/channel_factory.h"
#include "io/readings_csv.h"
#include "io/scenario_yaml.h"
#include "cli/commands.h"
#include "io/world_source.h"
#include "core/error.h"
#include "core/simulation.h"
#include "core/thread_count.h"

namespace rfidray::cli {
namespace {

struct SimulateOptions {
  std::string scenario;
  std::optional<uint64_t> seed;
  int threads = 0;
  std::string output_dir = "out";
  std::string channel;
  std::string model;  // "" keeps each antenna's own
  bool quiet = false;
  io::WorldSourceOptions world;          // --world instead of SCENARIO
  std::optional<double> duration_s;  // overrides the scenario's duration_s
};

// SIGINT / SIGTERM: the handler removes the temporary being written (io/atomic_file.h), says what was
// finished and exits 130 / 143. Files already renamed are complete; nothing partial stays under a final name.
// The progress line is prepared by the main thread (two buffers, switched atomically) so the handler only
// calls write(2), unlink(2) and _exit(2).
char g_progress[2][8192];
std::atomic<int> g_progress_slot{-1};

void set_progress(const std::string& text) {
  const int slot = g_progress_slot.load() == 0 ? 1 : 0;
  const size_t n = std::min(text.size(), sizeof g_progress[slot] - 1);
  std::memcpy(g_progress[slot], text.data(), n);
  g_progress[slot][n] = '\0';
  g_progress_slot.store(slot);
}

extern "C" void on_signal(int sig) {
  rfidray::io::remove_partial_output();
  const char* head = sig == SIGINT ? "\nrfidray: interrupted (SIGINT): " : "\nrfidray: terminated (SIGTERM): ";
  (void)!::write(2, head, std::strlen(head));
  const int slot = g_progress_slot.load();
  if (slot >= 0) (void)!::write(2, g_progress[slot], std::strlen(g_progress[slot]));
  (void)!::write(2, "\n", 1);
  ::_exit(128 + sig);
}

void install_signal_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

void write_file(const std::filesystem::path& path, const std::function<void(std::ostream&)>& body,
                std::string& done) {
  set_progress("writing " + path.string() + " (removed, not complete)" +
               (done.empty() ? std::string("; no output file was finished") : "; finished: " + done));
  io::write_file_atomic(path, body, "output file (check -o DIR)");
  done += (done.empty() ? "" : ", ") + path.string();
}

int run(const SimulateOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  set_progress("while loading the scenario; no output written");
  install_signal_handlers();
  Scenario scenario;
  std::shared_ptr<const Scene> world_scene;  // --world: the world's surfaces (a scenario loads its own scene)
  if (!o.world.file.empty()) {
    if (!o.scenario.empty()) throw InputError("give a SCENARIO file or --world FILE, not both");
    if (!o.duration_s)
      throw InputError("--world " + o.world.file + ": --duration S is required (the world's antennas and tags stand "
                       "where the world puts them, so no motion ends the run)");
    const io::WorldSource world = io::load_world_source(o.world);
    if (!o.quiet) std::fprintf(stderr, "rfidray: %s\n", world.summary.c_str());
    io::print_world_remarks(world);
    scenario = world.scenario;
    world_scene = world.scene;
  } else {
    if (o.scenario.empty()) throw InputError("give a SCENARIO file (or --world FILE)");
    scenario = io::load_scenario(o.scenario);
  }
  if (o.duration_s) scenario.duration_s = *o.duration_s;
  if (o.seed) scenario.seed = *o.seed;
  if (!o.channel.empty()) scenario.channel = parse_channel_level(o.channel, "--channel");
  if (!o.model.empty())
    for (AntennaSpec& a : scenario.antennas)
      a.reader.model = o.model == "physical" ? ReaderModelKind::kPhysical : ReaderModelKind::kPaper;
  // The paper model (eq. 4-5) uses only the distance: a traced channel would be computed and ignored.
  const bool any_physical = std::any_of(scenario.antennas.begin(), scenario.antennas.end(), [](const AntennaSpec& a) {
    return a.reader.model == ReaderModelKind::kPhysical;
  });
  if (scenario.channel != ChannelLevel::kIdeal && !any_physical)
    std::fprintf(stderr,
                 "rfidray: warning: channel '%s' has no effect: every antenna uses the paper reader model, which "
                 "depends on the distance only (use --model physical or `model: physical`)\n",
                 to_string(scenario.channel));
  const SceneMotion motion = build_motion(scenario);  // once per run: the channel (auto) and the loop share it
  std::vector<std::string> channel_report;
  const std::unique_ptr<Channel> channel =
      world_scene ? make_channel(scenario.channel, scenario, motion, world_scene, &channel_report)
                  : make_channel(scenario.channel, scenario, motion, &channel_report);
  SimulationOptions sim;
  const ThreadCount threads = startable_threads(o.threads, "--threads");
  if (!threads.note.empty()) std::fprintf(stderr, "rfidray: warning: %s\n", threads.note.c_str());
  sim.threads = threads.threads;
  set_progress("during the simulation; no output written");
  const SimulationResult result = simulate(scenario, motion, *channel, sim);
  if (!o.quiet)
    for (const std::string& note : result.notes) std::fprintf(stderr, "rfidray: note: %s\n", note.c_str());

  const std::filesystem::path dir(o.output_dir);
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw InputError(o.output_dir + ": cannot create output directory (" + ec.message() + ")");
  std::string done;
  for (size_t a = 0; a < scenario.antennas.size(); ++a)
    write_file(dir / (scenario.antennas[a].reader.name + ".csv"),
               [&](std::ostream& out) { io::write_readings_csv(out, scenario, a, result.antennas[a]); }, done);
  write_file(dir / "tags.csv", [&](std::ostream& out) { io::write_tags_csv(out, scenario, motion); }, done);
  const bool moving = io::has_moving_tags(motion);
  if (moving) {
    double rate = 0.0;
    for (const AntennaSpec& a : scenario.antennas) rate = std::max(rate, a.reader.update_rate_hz);
    write_file(dir / "tags_trajectory.csv", [&](std::ostream& out) {
      io::write_tag_trajectories_csv(out, scenario, motion, result.duration_s, rate);
    }, done);
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (o.quiet) return 0;

  std::printf("rfidray simulate %s: channel %s, seed %llu, %.3f s simulated\n",
              (o.world.file.empty() ? o.scenario : o.world.file).c_str(),
              (scenario.channel == ChannelLevel::kAuto ? "auto -> " + channel->name()
                                                       : std::string(to_string(scenario.channel))).c_str(),
              static_cast<unsigned long long>(scenario.seed), result.duration_s);
  for (const std::string& line : channel_report) std::printf("  %s\n", line.c_str());
  for (size_t a = 0; a < scenario.antennas.size(); ++a) {
    const AntennaResult& r = result.antennas[a];
    std::vector<uint64_t> per_tag(scenario.tags.size(), 0);
    for (const ReadRecord& rec : r.reads) ++per_tag[rec.tag];
    const std::string file = (dir / (scenario.antennas[a].reader.name + ".csv")).string();
    std::printf(r.gen2 ? "  antenna %s (%s model, Gen2): %llu slots, %llu reads of %llu acknowledged replies -> %s\n"
                       : "  antenna %s (%s model): %llu ticks, %llu reads of %llu attempts -> %s\n",
                scenario.antennas[a].reader.name.c_str(),
                scenario.antennas[a].reader.model == ReaderModelKind::kPaper ? "paper" : "physical",
                static_cast<unsigned long long>(r.ticks), static_cast<unsigned long long>(r.reads.size()),
                static_cast<unsigned long long>(r.attempts), file.c_str());
    if (r.gen2) {
      // A Gen2 reader's port: its slots by outcome and the reads per second of each tag.
      const Gen2SlotStats& g = *r.gen2;
      const double slots = std::max<double>(1.0, static_cast<double>(g.slots()));
      std::printf("    gen2: %llu rounds, %llu slots: empty %llu (%.1f %%), single %llu (%.1f %%), collided %llu "
                  "(%.1f %%, %llu captured); %llu reads, %.1f reads/s\n",
                  static_cast<unsigned long long>(g.rounds), static_cast<unsigned long long>(g.slots()),
                  static_cast<unsigned long long>(g.empty), 100.0 * g.empty / slots,
                  static_cast<unsigned long long>(g.single), 100.0 * g.single / slots,
                  static_cast<unsigned long long>(g.collided), 100.0 * g.collided / slots,
                  static_cast<unsigned long long>(g.captured), static_cast<unsigned long long>(g.reads),
                  result.duration_s > 0.0 ? g.reads / result.duration_s : 0.0);
      size_t n_read = 0;
      uint64_t lo = UINT64_MAX, hi = 0;
      for (uint64_t c : per_tag)
        if (c > 0) ++n_read, lo = std::min(lo, c), hi = std::max(hi, c);
      if (n_read > 0 && result.duration_s > 0.0)
        std::printf("    reads per second per tag (the %zu tags read): mean %.2f, min %.2f, max %.2f\n", n_read,
                    static_cast<double>(r.reads.size()) / n_read / result.duration_s, lo / result.duration_s,
                    hi / result.duration_s);
    }
    std::string line = "   ";
    for (size_t i = 0; i < scenario.tags.size(); ++i) {
      char cell[128];
      if (r.gen2 && result.duration_s > 0.0)
        std::snprintf(cell, sizeof cell, " %s:%.2f/s", scenario.tags[i].tag.name.c_str(), per_tag[i] / result.duration_s);
      else
        std::snprintf(cell, sizeof cell, " %s:%llu", scenario.tags[i].tag.name.c_str(),
                      static_cast<unsigned long long>(per_tag[i]));
      if (line.size() + std::strlen(cell) > 100) {
        std::printf("%s\n", line.c_str());
        line = "   ";
      }
      line += cell;
    }
    if (line.size() > 3) std::printf("%s\n", line.c_str());
  }
  if (result.channel_evaluations > 0)
    std::printf("  channel %s: %llu link evaluations (unchanged links reuse their last value)\n",
                channel->name().c_str(), static_cast<unsigned long long>(result.channel_evaluations));
  std::printf("  ground truth -> %s%s\n", (dir / "tags.csv").string().c_str(),
              moving ? (", " + (dir / "tags_trajectory.csv").string()).c_str() : "");
  std::printf("  wall time %.3f s (%d thread%s)\n", wall_s, threads.threads, threads.threads == 1 ? "" : "s");
  return 0;
}

}  // namespace

std::function<int()> setup_simulate(CLI::App& app) {
  auto opts = std::make_shared<SimulateOptions>();
  const std::string channels = channel_level_names();
  CLI::App* cmd = app.add_subcommand("simulate", "Run a scenario; write readings CSV per antenna and tag ground truth");
  cmd->footer(
      "Every antenna reads every present tag at its update rate along its trajectory (fixed, on a robot\n"
      "following waypoints with the paper's differential-drive kinematics, on a mast, or along waypoints).\n"
      "Output in DIR:\n"
      "  <antenna>.csv  time,posx,posy,posz,q1,q2,q3,q4,name,dist,phase,rssi,antenna,frequency_hz,channel\n"
      "                 (antenna position m and quaternion x,y,z,w; tag name; true distance m; phase rad in\n"
      "                 [0, 2pi); RSSI; antenna name; carrier Hz; hop channel index), successful reads only\n"
      "  tags.csv       name,x,y,z  (tag positions at t = 0)\n"
      "  tags_trajectory.csv  time,name,x,y,z  (only when tags move)\n"
      "The same seed gives byte-identical files at any --threads. Errors name the file, line and field and\n"
      "exit with status 2; unknown keys are errors.\n"
      "\n"
      "Scenario YAML (example: scenes/paper_warehouse.yaml):\n"
      "  seed, duration_s (default: until the robots / moving tags finish), channel, model (paper|physical),\n"
      "  channel_options: {candidates: exact|exhaustive, candidate_rays, candidate_spread, drop_below_db,\n"
      "         max_path_length_m, thin_post_max_width_m, double_diffraction_max_m, auto_phase_tolerance_rad,\n"
      "         auto_rssi_tolerance_db, auto_sample_links}\n"
      "  (channel: ideal|los|los+blocked|single-bounce|double-bounce|full-selective|full|auto; auto samples the scenario's\n"
      "  links and picks the cheapest of ideal, los, los+blocked, single-bounce, double-bounce, full-selective, full whose p95\n"
      "  phase and RSSI errors against full (exhaustive) stay within the tolerances, default 0.05 rad and\n"
      "  0.5 dB; it prints what it picked and why)\n"
      "  scene: {meshes: [{file, material}], materials, material_map, default_material}\n"
      "  robot: {name, waypoints: [[x,y],..], speed_m_s | wheel_speed_rad_s, wheel_radius_m, track_width_m,\n"
      "         turn_rate_rad_s | turn_wheel_speed_rad_s, initial_heading_deg, start_s}   (or robots: [..])\n"
      "  antennas: - name, model, frequency (Hz) | frequencies_hz: [..] | hopping: eu, phase_offset_rad(s),\n"
      "              hop_dwell_s, noisephi, noiserssi, range, range_sigma, optional_distribution(_params),\n"
      "              communication_gain, update_rate, tx_power_dbm, phase_bits, rssi_resolution_db,\n"
      "              sensitivity_dbm, modulation_factor, noise_rssi_db, gain_dbi, pattern, polarization,\n"
      "              start_s, and position [+ rpy_deg | yaw_deg | quaternion] | robot: NAME + mount: {position,\n"
      "              rpy_deg} | waypoints + speed_m_s; optional mast: {z_min_m, z_max_m, speed_m_s}\n"
      "  An antenna with gen2: {preset: max_throughput|dense_reader_m4 | tari_us, blf_khz, encoding: fm0|miller2|\n"
      "         miller4|miller8, trext; session 0-3, target A|B|AB, q, q_algorithm fixed|adaptive, q_c,\n"
      "         ports: [{antenna, dwell_ms}], select_prefix, capture_db} is an EPC Gen2 reader: it and its ports\n"
      "         read by inventory rounds, one row per read at the end of its EPC reply (docs/air-protocol.md)\n"
      "  tags: - name, position [+ orientation] | waypoints + speed_m_s, gain_dbi, chip_sensitivity_dbm,\n"
      "          pattern, polarization, start_s\n"
      "The seed Gazebo plugin's parameter names (frequency, noisephi, noiserssi, range, optional_distribution,\n"
      "optional_distribution_params, communication_gain, update_rate) are accepted as-is.\n"
      "\n"
      "--world FILE reads a Gazebo SDF world instead: collision geometry (mesh, box, cylinder, sphere, plane),\n"
      "antennas (<sensor type=\"rfid\"> with the seed plugin's parameters, or type=\"custom\" with <rfid_antenna>)\n"
      "and tags (<sensor type=\"rfidtag\">, or <rfid_tag>); model:// URIs through --resource-path and\n"
      "IGN_GAZEBO_RESOURCE_PATH / GZ_SIM_RESOURCE_PATH / SDF_PATH; radio materials from --materials FILE.\n"
      "Antennas and tags stand still, so --duration is required.");
  cmd->add_option("SCENARIO", opts->scenario, "Scenario YAML file (e.g. scenes/paper_warehouse.yaml), or --world");
  add_world_options(*cmd, opts->world);
  cmd->add_option("--duration", opts->duration_s, "Simulated time (s), overrides `duration_s`; required with --world");
  cmd->add_option("--seed", opts->seed, "Random seed (overrides the scenario's `seed`), >= 0")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--threads", opts->threads, "OpenMP threads (default: OMP_NUM_THREADS or all cores), 1…1024")
      ->check(CLI::Range(1, 1024));
  cmd->add_option("-o,--output", opts->output_dir, "Output directory, created if missing")->capture_default_str();
  cmd->add_option("--channel", opts->channel, "Channel model, overrides the scenario's `channel` (" + channels + ")");
  cmd->add_option("--model", opts->model, "Reader model of every antenna, overrides the scenario (paper | physical)")
      ->check(CLI::IsMember({"paper", "physical"}));
  cmd->add_flag("-q,--quiet", opts->quiet, "Print nothing on success");
  return [opts] { return run(*opts); };
}

}  // namespace rfidray::cli
