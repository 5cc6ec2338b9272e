#include "adapters/gazebo/live_world.h"

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cmath>
#include <cstdio>

#include "raytrace/channel_factory.h"
#include "core/error.h"
#include "core/reader_model.h"

namespace rfidray::gazebo {

LiveWorld::LiveWorld(GazeboWorld world, const LiveOptions& options)
    : world_(std::move(world)), options_(options) {
  world_.scenario.seed = options_.seed;
  world_.scenario.channel = options_.channel;
  // `auto` judges levels on links sampled over a run's motion; live poses come from Gazebo tick by tick.
  if (options_.channel == ChannelLevel::kAuto)
    throw InputError("--channel auto: the live bridge needs a fixed level (ideal, los, los+blocked, single-bounce); "
                     "pick one with `rfidray simulate --world ... --channel auto` on the same world");
  moves_scene_.assign(world_.entities.size(), false);
  for (const Collision& c : world_.collisions)
    for (int e = static_cast<int>(c.link); e >= 0; e = world_.entities[e].parent) moves_scene_[e] = true;
  next_tick_.assign(world_.scenario.antennas.size(), 0);
  for (const AntennaSpec& a : world_.scenario.antennas)
    needs_trace_ = needs_trace_ || (a.reader.model == ReaderModelKind::kPhysical && options_.channel != ChannelLevel::kIdeal);
  for (size_t a = 0; a < world_.scenario.antennas.size(); ++a)
    validate(world_.scenario.antennas[a].reader, "antenna '" + world_.scenario.antennas[a].reader.name + "'");
}

const Channel& LiveWorld::channel() {
  if (!channel_ || (needs_trace_ && scene_dirty_)) {
    channel_ = make_channel(options_.channel, world_.scenario.channel_options, build_scene(world_));
    ++scene_builds_;
  }
  scene_dirty_ = false;
  return *channel_;
}

void LiveWorld::emit_until(double t_s, const TickSink& sink, size_t& emitted) {
  const Scenario& s = world_.scenario;
  while (true) {
    // The earliest pending tick before t_s (ties: lower antenna index first).
    size_t best = s.antennas.size();
    double best_t = 0.0;
    for (size_t a = 0; a < s.antennas.size(); ++a) {
      const double t = static_cast<double>(next_tick_[a]) / s.antennas[a].reader.update_rate_hz;
      if (!(t < t_s) || t > options_.duration_s) continue;
      if (best == s.antennas.size() || t < best_t) best = a, best_t = t;
    }
    if (best == s.antennas.size()) return;
    world_.place_sensors();
    std::vector<Pose> tag_poses(s.tags.size());
    std::vector<size_t> present(s.tags.size());
    for (size_t i = 0; i < s.tags.size(); ++i) tag_poses[i] = s.tags[i].motion.pose, present[i] = i;
    const ReaderParams& reader = s.antennas[best].reader;
    TickReadings out;
    out.antenna = best;
    out.tick = next_tick_[best];
    out.time_s = best_t;
    out.antenna_pose = s.antennas[best].motion.pose;
    if (pose_provider_)
      if (const std::optional<Pose> p = pose_provider_(best, best_t)) out.antenna_pose = *p;
    const size_t c = hop_index_at(reader, best_t);
    out.frequency_hz = reader.frequencies_hz[c];
    out.hop_index = static_cast<uint32_t>(c);
    const Channel& ch = reader.model == ReaderModelKind::kPhysical ? channel() : static_cast<const Channel&>(ideal_);
    // Tag antennas and what backs them: resolved once, at the tags' first poses (core/tag_couplings.h).
    if (!couplings_) couplings_.emplace(s, std::span<const Pose>(tag_poses), channel());
    out.reads = simulate_tick(s, ch, best, out.tick, out.antenna_pose, tag_poses, present, &*couplings_);
    ++next_tick_[best];
    ++ticks_;
    ++emitted;
    sink(out);
  }
}

namespace {
std::atomic<bool> g_stop_requested{false};
void on_stop_signal(int) { g_stop_requested = true; }
}  // namespace

void install_stop_handlers() {
  std::signal(SIGINT, on_stop_signal);
  std::signal(SIGTERM, on_stop_signal);
}
bool stop_requested() { return g_stop_requested; }

GazeboWorld load_bridge_world(const WorldOptions& options, const std::string& model) {
  GazeboWorld world = load_world(options);
  for (const auto& w : world.warnings) std::fprintf(stderr, "rfidray: warning: %s\n", w.c_str());
  for (const auto& n : world.notes) std::fprintf(stderr, "rfidray: note: %s\n", n.c_str());
  if (world.scenario.antennas.empty())
    throw InputError(options.file + ": no RFID antenna in the world: nothing to read");
  if (!model.empty())
    for (AntennaSpec& a : world.scenario.antennas)
      a.reader.model = model == "physical" ? ReaderModelKind::kPhysical : ReaderModelKind::kPaper;
  return world;
}

size_t LiveWorld::advance(double t_s, const TickSink& sink, bool* restarted) {
  size_t emitted = 0;
  if (restarted) *restarted = false;
  if (!std::isfinite(t_s)) return 0;
  // Simulation time a second or more back: the simulator was reset. Ticks start again from there.
  if (started_ && t_s + 1.0 < time_s_) {
    started_ = false;
    time_s_ = t_s;
    if (restarted) *restarted = true;
  }
  if (!started_) {
    started_ = true;
    for (size_t a = 0; a < next_tick_.size(); ++a)
      next_tick_[a] = static_cast<uint64_t>(std::ceil(t_s * world_.scenario.antennas[a].reader.update_rate_hz - 1e-9));
  } else if (t_s > time_s_) {
    emit_until(t_s, sink, emitted);
  }
  // An older stamp (another pose topic, a step behind) still updates poses: the latest value wins.
  time_s_ = std::max(time_s_, t_s);
  return emitted;
}

void LiveWorld::set_entity_pose(size_t entity, const Pose& relative_pose) {
  Entity& e = world_.entities.at(entity);
  if (moves_scene_[entity] && !(e.pose == relative_pose)) scene_dirty_ = true;
  e.pose = relative_pose;
}

void LiveWorld::set_antenna_mount_pose(size_t antenna, const Pose& pose) { world_.antenna_mounts.at(antenna).pose = pose; }
void LiveWorld::set_tag_mount_pose(size_t tag, const Pose& pose) { world_.tag_mounts.at(tag).pose = pose; }

size_t LiveWorld::apply(double t_s, const ignition::msgs::Pose_V& poses, const TickSink& sink) {
  if (!std::isfinite(t_s)) return 0;
  const size_t emitted = advance(t_s, sink);
  for (const auto& p : poses.pose()) {
    const auto ref = resolve(map_, world_, p);
    if (!ref) continue;
    const std::optional<Pose> checked = checked_from_msg(p);
    if (!checked) {
      // A malformed pose (NaN, inf, beyond the coordinate range, zero quaternion) is dropped: the entity keeps
      // its last pose, and the count goes to /rfid/status.
      if (rejected_poses_++ == 0)
        first_rejected_pose_ = "entity id " + std::to_string(p.id()) + " ('" + clip(p.name()) + "') at t = " +
                               std::to_string(t_s) + " s";
      continue;
    }
    const Pose& pose = *checked;
    if (ref->kind == EntityRef::Kind::kAntenna) {
      set_antenna_mount_pose(ref->index, pose);
    } else if (ref->kind == EntityRef::Kind::kTag) {
      set_tag_mount_pose(ref->index, pose);
    } else {
      set_entity_pose(ref->index, pose);
    }
  }
  return emitted;
}

bool LiveWorld::finished() const {
  if (!started_) return false;
  for (size_t a = 0; a < next_tick_.size(); ++a)
    if (static_cast<double>(next_tick_[a]) / world_.scenario.antennas[a].reader.update_rate_hz <= options_.duration_s)
      return false;
  return true;
}

}  // namespace rfidray::gazebo
