#pragma once
// Module core — owns the physics (antenna patterns, polarization, Fresnel, materials), the reader model
// (phase, RSSI, noise, quantization, read/no-read), motion and the simulation loop. Eigen and OpenMP only;
// includes nothing outside core/.
//
// The simulation loop: every antenna reads at its update rate over the scenario duration; at each tick the
// antenna pose, the hop channel and every present tag give one read attempt through the reader model.
// Work items are (antenna, block of ticks), run in parallel with OpenMP; each tick draws from its own
// random stream make_stream(seed, {antenna, tick}), so the result is identical at any thread count.
#include <complex>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/channel.h"
#include "core/differential_drive.h"
#include "core/gen2_inventory.h"
#include "core/reader.h"
#include "core/scenario.h"
#include "core/trajectory.h"

namespace rfidray {

class TagCouplings;

// Antenna–tag distances below this count as "the tag is at the antenna" (an input error).
inline constexpr double kMinLinkDistance_m = 1e-6;

// The trajectories of a scenario, index-aligned with its robots, antennas and tags.
struct SceneMotion {
  std::vector<std::shared_ptr<const DifferentialDriveTrajectory>> robots;
  std::vector<TrajectoryPtr> antennas;
  std::vector<TrajectoryPtr> tags;
};

// Builds one trajectory (see MotionSpec for the composition). `owner` names the antenna or tag in errors.
TrajectoryPtr build_trajectory(const Scenario& scenario, const SceneMotion& motion, const MotionSpec& spec,
                               double start_s, const std::string& owner);
// Throws InputError (prefixed with the scenario file and the owner's line) on bad motion parameters.
SceneMotion build_motion(const Scenario& scenario);

// scenario.duration_s if set; else the time the last robot or waypoint motion ends. Throws InputError
// when neither exists (nothing to end the run).
double scenario_duration_s(const Scenario& scenario, const SceneMotion& motion);

// Hop index at time t (into reader.frequencies_hz): carriers are visited in list order, hop_dwell_s each,
// cyclically.
size_t hop_index_at(const ReaderParams& reader, double t_s);

struct ReadRecord {
  double time_s = 0.0;
  uint64_t tick = 0;
  uint32_t tag = 0;  // index into Scenario::tags
  Pose antenna_pose;
  double distance_m = 0.0;  // true distance
  double frequency_hz = 0.0;
  uint32_t hop_index = 0;  // index into the reader's frequencies_hz (the CSV's `channel` column)
  Reading reading;
};

struct AntennaResult {
  std::vector<ReadRecord> reads;  // successful reads only, ordered by (tick, tag)
  uint64_t ticks = 0;             // ticks at which the antenna was active
  uint64_t attempts = 0;          // (tick, present tag) pairs
  // A Gen2 reader's port (core/gen2_simulation.h): its slot statistics; `ticks` counts its slots, `attempts` its
  // acknowledged replies, and reads are ordered by time.
  std::optional<Gen2SlotStats> gen2;
};

struct SimulationOptions {
  int threads = 0;               // 0: OpenMP default
  uint64_t ticks_per_block = 64;  // work-item size; results do not depend on it
};

struct SimulationResult {
  double duration_s = 0.0;
  std::vector<AntennaResult> antennas;  // index-aligned with Scenario::antennas
  uint64_t channel_evaluations = 0;     // links handed to Channel::one_way (after caching)
  std::vector<std::string> notes;       // for the user: e.g. what tags' scene mounts found (core/tag_couplings.h)
  // Tags whose start position lies where the channel's level is outside its validity (core/level_validity.h:
  // too close to a metal edge for the level's measured error to stay within 0.1 of the free-space field).
  size_t tags_outside_validity = 0;
};

// Runs the scenario along `motion` (build_motion(scenario), built once per run by the caller). Throws InputError
// for bad inputs (e.g. a tag at an antenna: names both).
SimulationResult simulate(const Scenario& scenario, const SceneMotion& motion, const Channel& channel,
                          const SimulationOptions& options = {});
// The same, building the motion.
SimulationResult simulate(const Scenario& scenario, const Channel& channel, const SimulationOptions& options = {});

// Where an antenna's waves start: its reported pose moved by the reader's phase-centre offset (antenna frame).
Pose phase_centre_pose(const ReaderParams& reader, const Pose& antenna_pose);

// The read attempts of one antenna tick, as simulate() makes them: tags `present` (ascending indices into
// Scenario::tags) in that order, every draw from make_stream(seed, {antenna, tick}), the hop channel of t_s.
// distance_m (from the phase centre), tag_pose and h_one_way are indexed by tag (h only read for the physical
// model, tag_pose only when a phase pattern is set). antenna_pose is the reported (mounting) pose. Successful
// reads are appended to `out`.
// `couplings` (optional): the tags' antennas, chips and mounts (core/tag_couplings.h; physical model); tag_pose
// is then read for every tag with an antenna.
void read_attempts(const Scenario& scenario, size_t antenna, uint64_t tick, double t_s, const Pose& antenna_pose,
                   std::span<const size_t> present, std::span<const double> distance_m,
                   std::span<const Pose> tag_pose, std::span<const std::complex<double>> h_one_way,
                   std::vector<ReadRecord>& out, const TagCouplings* couplings = nullptr);

// One tick of one antenna from poses given from outside (a live bridge), at t = tick / update_rate like
// simulate(): the channel is evaluated for the present tags (physical model only) and read_attempts draws.
// For the same poses and seed it returns exactly the reads simulate() makes at that tick. tag_poses is
// indexed by tag. Throws InputError when a tag is at the antenna. `couplings`: the run's TagCouplings (built once
// by the caller; null: every tag a point tag, as for a scenario without tag antennas).
std::vector<ReadRecord> simulate_tick(const Scenario& scenario, const Channel& channel, size_t antenna,
                                      uint64_t tick, const Pose& antenna_pose, std::span<const Pose> tag_poses,
                                      std::span<const size_t> present, const TagCouplings* couplings = nullptr);

}  // namespace rfidray
