#include "core/simulation.h"

#include "core/level_validity.h"

#include "core/tag_couplings.h"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/gen2_simulation.h"
#include "core/limits.h"
#include "core/mast.h"
#include "core/number_text.h"
#include "core/random.h"
#include "core/reader_model.h"
#include "core/waypoint_trajectory.h"

namespace rfidray {
namespace {

std::string where(const Scenario& s, int line) {
  if (s.source.empty()) return "";
  return line > 0 ? s.source + ":" + std::to_string(line) + ": " : s.source + ": ";
}

// Re-raises an InputError with the scenario location in front.
template <typename F>
auto located(const Scenario& s, int line, F&& f) {
  try {
    return f();
  } catch (const InputError& e) {
    throw InputError(where(s, line) + e.what());
  }
}

struct CachedLink {
  bool valid = false;
  Pose antenna_pose, tag_pose;
  std::complex<double> h{0.0, 0.0};
};

}  // namespace

Pose phase_centre_pose(const ReaderParams& reader, const Pose& antenna_pose) {
  if (reader.phase_centre_offset_m.isZero(0.0)) return antenna_pose;
  return Pose{antenna_pose.transform_point(reader.phase_centre_offset_m), antenna_pose.orientation};
}

void read_attempts(const Scenario& scenario, size_t antenna, uint64_t tick, double t_s, const Pose& antenna_pose,
                   std::span<const size_t> present, std::span<const double> distance_m,
                   std::span<const Pose> tag_pose, std::span<const std::complex<double>> h_one_way,
                   std::vector<ReadRecord>& out, const TagCouplings* couplings) {
  const ReaderParams& reader = scenario.antennas[antenna].reader;
  const size_t c = hop_index_at(reader, t_s);
  const bool physical = reader.model == ReaderModelKind::kPhysical;
  const Pose centre = phase_centre_pose(reader, antenna_pose);
  Rng rng = make_stream(scenario.seed, {static_cast<uint64_t>(antenna), tick});
  for (size_t i : present) {
    LinkState link;
    link.distance_m = distance_m[i];
    link.frequency_hz = reader.frequencies_hz[c];
    link.phase_offset_rad = reader.phase_offsets_rad[c];
    link.hop_index = c;
    link.h_one_way = physical ? h_one_way[i] : std::complex<double>{0.0, 0.0};
    if (couplings && physical) {
      link.tag_coupling = couplings->at(i, antenna, c);
      // A backing that is not in the scene adds its image path (a meshed one is the channel's own path).
      if (link.tag_coupling)
        link.h_one_way *= backing_image_factor(couplings->backings()[i], tag_pose[i], centre.position, link.frequency_hz);
    }
    const PhasePattern& tag_pattern = scenario.tags[i].tag.phase_pattern;
    if (!reader.phase_pattern.empty() || !tag_pattern.empty()) {
      // Along the direct direction (a ray-traced channel's other paths get the same shift: an approximation).
      const Vec3 to_tag = tag_pose[i].position - centre.position;
      link.pattern_phase_rad = reader.phase_pattern.phase_rad(centre.to_local_direction(to_tag)) +
                               tag_pattern.phase_rad(tag_pose[i].to_local_direction(-to_tag));
    }
    const Reading reading = read_tag(reader, scenario.tags[i].tag, link, rng);
    if (!reading.read) continue;
    out.push_back({t_s, tick, static_cast<uint32_t>(i), antenna_pose, distance_m[i], link.frequency_hz,
                   static_cast<uint32_t>(c), reading});
  }
}

std::vector<ReadRecord> simulate_tick(const Scenario& scenario, const Channel& channel, size_t antenna,
                                      uint64_t tick, const Pose& antenna_pose, std::span<const Pose> tag_poses,
                                      std::span<const size_t> present, const TagCouplings* couplings) {
  const ReaderParams& reader = scenario.antennas.at(antenna).reader;
  const double t_s = static_cast<double>(tick) / reader.update_rate_hz;
  const size_t n_tags = scenario.tags.size();
  std::vector<double> dist(n_tags, 0.0);
  std::vector<std::complex<double>> h(n_tags, {0.0, 0.0});
  std::vector<Endpoint> batch;
  const Pose centre = phase_centre_pose(reader, antenna_pose);
  for (size_t i : present) {
    dist[i] = (tag_poses[i].position - centre.position).norm();
    if (!(dist[i] >= kMinLinkDistance_m))
      throw InputError("tag '" + scenario.tags[i].tag.name + "' is at antenna '" + reader.name + "' at t = " +
                       num(t_s) + " s (distance " + num(dist[i]) + " m; the models need D > 0)");
    batch.push_back({tag_poses[i], scenario.tags[i].tag.pattern, scenario.tags[i].tag.polarization});
  }
  if (reader.model == ReaderModelKind::kPhysical && !batch.empty()) {
    std::vector<std::complex<double>> batch_h(batch.size());
    channel.one_way({centre, reader.pattern, reader.polarization}, batch,
                    reader.frequencies_hz[hop_index_at(reader, t_s)], batch_h);
    for (size_t m = 0; m < present.size(); ++m) h[present[m]] = batch_h[m];
  }
  std::vector<ReadRecord> out;
  read_attempts(scenario, antenna, tick, t_s, antenna_pose, present, dist, tag_poses, h, out, couplings);
  return out;
}

TrajectoryPtr build_trajectory(const Scenario& scenario, const SceneMotion& motion, const MotionSpec& spec,
                               double start_s, const std::string& owner) {
  if (spec.kind == MotionSpec::Kind::kWaypoints) {
    if (spec.mast) throw InputError(owner + ": a mast needs a fixed or robot base, not waypoints");
    return std::make_shared<WaypointTrajectory>(spec.waypoints, spec.speed_m_s, spec.pose.orientation, start_s);
  }
  if (spec.kind == MotionSpec::Kind::kFixed && !spec.mast) return std::make_shared<StaticTrajectory>(spec.pose);
  TrajectoryPtr base;
  if (spec.kind == MotionSpec::Kind::kRobot) {
    for (size_t i = 0; i < scenario.robots.size(); ++i)
      if (scenario.robots[i].name == spec.robot) base = motion.robots.at(i);
    if (!base) throw InputError(owner + ": unknown robot '" + spec.robot + "'");
  } else {
    base = std::make_shared<StaticTrajectory>(Pose{});
  }
  if (spec.mast) base = std::make_shared<MastTrajectory>(base, *spec.mast);
  return std::make_shared<MountedTrajectory>(base, spec.pose);
}

SceneMotion build_motion(const Scenario& scenario) {
  SceneMotion m;
  for (const RobotSpec& r : scenario.robots)
    m.robots.push_back(located(scenario, r.source_line, [&] {
      return std::make_shared<const DifferentialDriveTrajectory>(r.waypoints, r.drive);
    }));
  for (const AntennaSpec& a : scenario.antennas)
    m.antennas.push_back(located(scenario, a.source_line, [&] {
      return build_trajectory(scenario, m, a.motion, a.start_s, "antenna '" + a.reader.name + "'");
    }));
  for (const TagSpec& t : scenario.tags)
    m.tags.push_back(located(scenario, t.source_line, [&] {
      return build_trajectory(scenario, m, t.motion, t.start_s, "tag '" + t.tag.name + "'");
    }));
  return m;
}

double scenario_duration_s(const Scenario& scenario, const SceneMotion& motion) {
  if (scenario.duration_s) {
    const double d = *scenario.duration_s;
    if (!(d >= 0.0) || !std::isfinite(d))
      throw InputError(where(scenario, 0) + "field 'duration_s': must be >= 0 and finite (got " + num(d) + ")");
    return d;
  }
  double end = 0.0;
  bool any = false;
  for (const auto& r : motion.robots) {
    end = std::max(end, r->end_time_s());
    any = true;
  }
  auto consider = [&](const MotionSpec& spec, const TrajectoryPtr& t) {
    if (spec.kind == MotionSpec::Kind::kWaypoints && std::isfinite(t->end_time_s())) {
      end = std::max(end, t->end_time_s());
      any = true;
    }
  };
  for (size_t i = 0; i < scenario.antennas.size(); ++i) consider(scenario.antennas[i].motion, motion.antennas[i]);
  for (size_t i = 0; i < scenario.tags.size(); ++i) consider(scenario.tags[i].motion, motion.tags[i]);
  if (!any)
    throw InputError(where(scenario, 0) +
                     "field 'duration_s': required when no robot or waypoint motion ends the run");
  return end;
}

size_t hop_index_at(const ReaderParams& reader, double t_s) {
  const size_t n = reader.frequencies_hz.size();
  if (n <= 1 || !(reader.hop_dwell_s > 0.0) || t_s <= 0.0) return 0;
  return static_cast<size_t>(std::floor(t_s / reader.hop_dwell_s)) % n;
}

SimulationResult simulate(const Scenario& scenario, const Channel& channel, const SimulationOptions& options) {
  return simulate(scenario, build_motion(scenario), channel, options);
}

namespace {

// Tags outside their level's validity (core/level_validity.h: near metal edges, narrow obstacles, penetrable slabs,
// parallel plates), at their and the antennas' start poses, for the channel's level: counted, and one note naming the worst. Levels are known by the channel's name (a traced level or ideal); another channel
// (a test double) is not judged.
// Each tag's verdict is its own (the channel is thread-safe), so the tags are judged in parallel and counted in
// tag order afterwards: the same count and note at any thread count. Serial, this was a third of `simulate`'s CPU
// time on a 100 k-triangle warehouse at `full` (edge ends: raytrace/edge_end_finder.h).
template <typename AntennaEndpoint, typename TagEndpoint>
void count_tags_outside_validity(const Scenario& scenario, const SceneMotion& motion, const Channel& channel,
                                 AntennaEndpoint&& antenna_endpoint, TagEndpoint&& tag_endpoint, int threads,
                                 SimulationResult& result) {
  const std::optional<ChannelLevel> judged = judged_level(channel);
  if (!judged || scenario.antennas.empty() || scenario.tags.empty()) return;
  const ChannelLevel level = *judged;
  const double f = scenario.antennas.front().reader.frequencies_hz.front();
  const size_t n_tags = scenario.tags.size();
  std::vector<LevelValidity> verdicts(n_tags);
  std::vector<std::exception_ptr> errors(n_tags);
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (size_t i = 0; i < n_tags; ++i) {
    try {
      const Endpoint tag = tag_endpoint(i, motion.tags.at(i)->pose_at(scenario.tags[i].start_s));
      // The tag's worst link among the antennas at their start poses.
      LevelValidity& v = verdicts[i];
      for (size_t a = 0; a < motion.antennas.size(); ++a) {
        const Endpoint antenna = antenna_endpoint(a, motion.antennas[a]->pose_at(scenario.antennas[a].start_s));
        const LevelValidity va = level_validity(level, link_sight(channel, antenna, tag, f), f);
        if (a == 0 || (!va.level_ok && (v.level_ok || va.estimated_error > v.estimated_error))) v = va;
      }
    } catch (...) {  // exceptions must not leave an OpenMP region; rethrown below in tag order
      errors[i] = std::current_exception();
    }
  }
  for (auto& e : errors)
    if (e) std::rethrow_exception(e);
  size_t worst = 0;
  LevelValidity worst_v;
  for (size_t i = 0; i < n_tags; ++i) {
    const LevelValidity& v = verdicts[i];
    if (v.level_ok) continue;
    if (result.tags_outside_validity++ == 0 || v.estimated_error > worst_v.estimated_error) worst = i, worst_v = v;
  }
  if (result.tags_outside_validity == 0) return;
  char b[320];
  std::snprintf(b, sizeof b, "%zu of %zu tags are where level %s is outside its validity or what was checked (near metal edges and edge ends, narrow obstacles, penetrable slabs, parallel plates, plates seen edge-on); the worst, tag '",
                result.tags_outside_validity, scenario.tags.size(), to_string(level));
  result.notes.push_back(std::string(b) + scenario.tags[worst].tag.name + "': " + worst_v.reason);
}

}  // namespace

SimulationResult simulate(const Scenario& scenario, const SceneMotion& motion, const Channel& channel,
                          const SimulationOptions& options) {
  SimulationResult result;
  result.duration_s = scenario_duration_s(scenario, motion);
  const size_t n_ant = scenario.antennas.size(), n_tags = scenario.tags.size();
  result.antennas.resize(n_ant);
  const bool cacheable = channel.cacheable();
  const std::vector<bool> gen2_driven = gen2_driven_antennas(scenario);  // run by simulate_gen2, not by ticks

  for (size_t a = 0; a < n_ant; ++a) {
    const ReaderParams& r = scenario.antennas[a].reader;
    located(scenario, scenario.antennas[a].source_line, [&] {
      validate(r, "antennas[" + std::to_string(a) + "]");
      return 0;
    });
    // Ticks k = 0 … ⌊duration·rate⌋: bounded before anything is allocated (a duration of 1e20 s must not wrap
    // the tick count to one tick).
    const double ticks = std::floor(result.duration_s * r.update_rate_hz + 1e-9) + 1.0;
    if (!(ticks <= limits::kMaxTicks))
      throw InputError(where(scenario, scenario.duration_s ? 0 : scenario.antennas[a].source_line) +
                       "field '" + (scenario.duration_s ? std::string("duration_s") : "antennas[" + std::to_string(a) + "].update_rate") +
                       "': " + num(result.duration_s) + " s at " + num(r.update_rate_hz) + " Hz is " + num(ticks) +
                       " ticks for antenna '" + r.name + "' (up to " + rounded_text(ticks * double(std::max<size_t>(1, n_tags)) * double(sizeof(ReadRecord)) / 1e9, 3) +
                       " GB of readings); at most " + num(limits::kMaxTicks) + " ticks per antenna");
  }

  for (size_t i = 0; i < n_tags; ++i)
    located(scenario, scenario.tags[i].source_line, [&] {
      validate(scenario.tags[i].tag, "tags[" + std::to_string(i) + "]");
      return 0;
    });

  // `pose` is the antenna's phase centre (phase_centre_pose).
  auto antenna_endpoint = [&](size_t a, const Pose& pose) {
    const ReaderParams& r = scenario.antennas[a].reader;
    return Endpoint{pose, r.pattern, r.polarization};
  };
  auto tag_endpoint = [&](size_t i, const Pose& pose) {
    const TagParams& t = scenario.tags[i].tag;
    return Endpoint{pose, t.pattern, t.polarization};
  };
  auto coincident_error = [&](size_t a, size_t i, double t_s, double d) {
    return InputError(where(scenario, scenario.tags[i].source_line) + "tag '" + scenario.tags[i].tag.name +
                      "' is at antenna '" + scenario.antennas[a].reader.name + "' at t = " + num(t_s) +
                      " s (distance " + num(d) + " m; the models need D > 0)");
  };
  auto needs_h = [&](size_t a) { return scenario.antennas[a].reader.model == ReaderModelKind::kPhysical; };

  // Tag antennas, chips and backings: resolved once, before the parallel loop (core/tag_couplings.h).
  const TagCouplings couplings(scenario, motion, channel);
  result.notes = couplings.notes();
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  count_tags_outside_validity(scenario, motion, channel, antenna_endpoint, tag_endpoint, threads, result);

  // Static links (antenna and tag both static) are computed once per channel frequency, up front.
  // static_h[a][c * n_tags + i]; empty when the antenna moves or does not need h.
  std::vector<std::vector<std::optional<std::complex<double>>>> static_h(n_ant);
  std::vector<std::pair<size_t, size_t>> static_jobs;  // (antenna, channel)
  for (size_t a = 0; a < n_ant; ++a) {
    if (gen2_driven[a] || !cacheable || !needs_h(a) || !motion.antennas[a]->is_static()) continue;
    static_h[a].resize(scenario.antennas[a].reader.frequencies_hz.size() * n_tags);
    for (size_t c = 0; c < scenario.antennas[a].reader.frequencies_hz.size(); ++c) static_jobs.push_back({a, c});
  }
  std::vector<std::exception_ptr> static_errors(static_jobs.size());
  std::vector<uint64_t> static_evals(static_jobs.size(), 0);
  const auto static_job = [&](size_t j) {
    const auto [a, c] = static_jobs[j];
    try {
      const Pose ap = phase_centre_pose(scenario.antennas[a].reader, motion.antennas[a]->pose_at(0.0));
      std::vector<Endpoint> ends;
      std::vector<size_t> index;
      for (size_t i = 0; i < n_tags; ++i) {
        if (!motion.tags[i]->is_static()) continue;
        const Pose tp = motion.tags[i]->pose_at(0.0);
        const double d = (tp.position - ap.position).norm();
        if (!(d >= kMinLinkDistance_m)) throw coincident_error(a, i, 0.0, d);
        ends.push_back(tag_endpoint(i, tp));
        index.push_back(i);
      }
      std::vector<std::complex<double>> h(ends.size());
      channel.one_way(antenna_endpoint(a, ap), ends, scenario.antennas[a].reader.frequencies_hz[c], h);
      static_evals[j] = ends.size();
      for (size_t k = 0; k < index.size(); ++k) static_h[a][c * n_tags + index[k]] = h[k];
    } catch (...) {  // exceptions must not leave an OpenMP region; rethrown below in job order
      static_errors[j] = std::current_exception();
    }
  };
  // One job per (antenna, carrier): with fewer jobs than threads, or a number that does not divide among them
  // (3 antennas on 2 threads), a parallel loop over jobs leaves threads idle. one_way splits its own tags over
  // every thread from Channel::threaded_batch_min_tags() on (64 tags up to single-bounce, 17 from double-bounce
  // up: raytrace/raytraced_channel.cpp), so with that many static tags and the default thread count the jobs run
  // one after another, each on all threads; otherwise the jobs are spread over the threads. The same h either
  // way (every link is computed on its own).
  size_t static_tags = 0;
  for (size_t i = 0; i < n_tags; ++i) static_tags += motion.tags[i]->is_static();
  if (static_tags >= channel.threaded_batch_min_tags() && threads == omp_get_max_threads()) {
    for (size_t j = 0; j < static_jobs.size(); ++j) static_job(j);
  } else {
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
    for (size_t j = 0; j < static_jobs.size(); ++j) static_job(j);
  }
  for (auto& e : static_errors)
    if (e) std::rethrow_exception(e);
  for (uint64_t n : static_evals) result.channel_evaluations += n;

  // Work items: blocks of consecutive ticks of one antenna.
  struct Item {
    size_t antenna;
    uint64_t tick0, tick1;  // [tick0, tick1)
    AntennaResult out;
    uint64_t evaluations = 0;
    std::exception_ptr error;
  };
  std::vector<Item> items;
  const uint64_t block = std::max<uint64_t>(1, options.ticks_per_block);
  for (size_t a = 0; a < n_ant; ++a) {
    if (gen2_driven[a]) continue;
    const double rate = scenario.antennas[a].reader.update_rate_hz;
    // Ticks at t = k / rate for k = 0 … ⌊duration·rate⌋ (the tolerance keeps an exact end tick).
    const uint64_t n_ticks = static_cast<uint64_t>(std::floor(result.duration_s * rate + 1e-9)) + 1;
    for (uint64_t k = 0; k < n_ticks; k += block) items.push_back({a, k, std::min(n_ticks, k + block), {}, 0, {}});
  }

#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (size_t w = 0; w < items.size(); ++w) {
    Item& item = items[w];
    const size_t a = item.antenna;
    const AntennaSpec& ant = scenario.antennas[a];
    const ReaderParams& reader = ant.reader;
    const size_t n_ch = reader.frequencies_hz.size();
    // Links whose two poses did not change since they were last computed on a channel reuse h.
    std::vector<CachedLink> cache(cacheable && needs_h(a) ? n_ch * n_tags : 0);
    std::vector<Pose> tag_pose(n_tags);
    std::vector<double> dist(n_tags);
    std::vector<std::complex<double>> h(n_tags);
    std::vector<size_t> present, missing;
    std::vector<Endpoint> batch;
    std::vector<std::complex<double>> batch_h;
    try {
      for (uint64_t k = item.tick0; k < item.tick1; ++k) {
        const double t = static_cast<double>(k) / reader.update_rate_hz;
        if (t < ant.start_s) continue;
        ++item.out.ticks;
        const Pose ap = motion.antennas[a]->pose_at(t);
        const Pose centre = phase_centre_pose(reader, ap);
        const size_t c = hop_index_at(reader, t);
        present.clear();
        for (size_t i = 0; i < n_tags; ++i) {
          if (t < scenario.tags[i].start_s) continue;
          tag_pose[i] = motion.tags[i]->pose_at(t);
          dist[i] = (tag_pose[i].position - centre.position).norm();
          if (!(dist[i] >= kMinLinkDistance_m)) throw coincident_error(a, i, t, dist[i]);
          present.push_back(i);
        }
        if (needs_h(a)) {
          missing.clear();
          batch.clear();
          for (size_t i : present) {
            if (!static_h[a].empty() && static_h[a][c * n_tags + i]) {
              h[i] = *static_h[a][c * n_tags + i];
              continue;
            }
            if (!cache.empty()) {
              const CachedLink& e = cache[c * n_tags + i];
              if (e.valid && e.antenna_pose == centre && e.tag_pose == tag_pose[i]) {
                h[i] = e.h;
                continue;
              }
            }
            missing.push_back(i);
            batch.push_back(tag_endpoint(i, tag_pose[i]));
          }
          if (!batch.empty()) {
            batch_h.resize(batch.size());
            channel.one_way(antenna_endpoint(a, centre), batch, reader.frequencies_hz[c], batch_h);
            item.evaluations += batch.size();
            for (size_t m = 0; m < missing.size(); ++m) {
              const size_t i = missing[m];
              h[i] = batch_h[m];
              if (!cache.empty()) cache[c * n_tags + i] = {true, centre, tag_pose[i], batch_h[m]};
            }
          }
        }
        item.out.attempts += present.size();
        read_attempts(scenario, a, k, t, ap, present, dist, tag_pose, h, item.out.reads, &couplings);
      }
    } catch (...) {
      item.error = std::current_exception();
    }
  }

  for (Item& item : items) {
    if (item.error) std::rethrow_exception(item.error);  // the first failing item in (antenna, tick) order
    AntennaResult& out = result.antennas[item.antenna];
    out.ticks += item.out.ticks;
    out.attempts += item.out.attempts;
    out.reads.insert(out.reads.end(), item.out.reads.begin(), item.out.reads.end());
    result.channel_evaluations += item.evaluations;
  }
  simulate_gen2(scenario, motion, channel, couplings, result.duration_s, threads, result);
  return result;
}

}  // namespace rfidray
