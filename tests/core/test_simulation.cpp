// The simulation loop: tick timing, ordering, hopping, start times, link caching, determinism across
// thread counts and block sizes, the h pipeline into the physical model, and input errors.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <set>

#include "core/error.h"
#include "core/simulation.h"
#include "tests/support/fixed_specs.h"
#include "core/units.h"

namespace rfidray {
namespace {

// Wraps the ideal channel, counting links evaluated; optionally claims not to be cacheable.
class CountingChannel final : public Channel {
 public:
  explicit CountingChannel(bool cacheable = true) : cacheable_(cacheable) {}
  std::string name() const override { return "counting"; }
  std::vector<Path> paths(const Endpoint& a, const Endpoint& t, double f) const override { return ideal_.paths(a, t, f); }
  void one_way(const Endpoint& a, std::span<const Endpoint> tags, double f,
               std::span<std::complex<double>> h) const override {
    links += tags.size();
    ideal_.one_way(a, tags, f, h);
  }
  bool cacheable() const override { return cacheable_; }
  mutable std::atomic<uint64_t> links{0};

 private:
  IdealChannel ideal_;
  bool cacheable_;
};

using testing::fixed_antenna;
using testing::fixed_tag;

Scenario static_scene() {
  Scenario s;
  s.antennas.push_back(fixed_antenna("A", Vec3(0, 0, 1)));
  s.tags.push_back(fixed_tag("t0", Vec3(1, 0, 1)));
  s.tags.push_back(fixed_tag("t1", Vec3(0, 2, 1)));
  s.tags.push_back(fixed_tag("t2", Vec3(0, 0, 4)));
  s.duration_s = 2.0;
  return s;
}

Scenario robot_scene() {
  Scenario s;
  RobotSpec r;
  r.waypoints = {Vec3(-1, -3, 0), Vec3(-1, 3, 0), Vec3(2, 3, 0)};
  r.drive.drive_wheel_speed_rad_s = 5.0;  // 0.5 m/s with r = 0.1
  s.robots.push_back(r);
  AntennaSpec mobile = fixed_antenna("mobile", Vec3(0, 0, 1.2));
  mobile.motion.kind = MotionSpec::Kind::kRobot;
  mobile.motion.robot = "robot";
  mobile.reader.frequencies_hz = {865.7e6, 866.3e6, 866.9e6, 867.5e6};
  mobile.reader.phase_offsets_rad = {0.1, 0.2, 0.3, 0.4};
  mobile.reader.hop_dwell_s = 0.4;
  s.antennas.push_back(mobile);
  s.antennas.push_back(fixed_antenna("fixed", Vec3(2, 0, 2)));
  for (int i = 0; i < 5; ++i) s.tags.push_back(fixed_tag("t" + std::to_string(i), Vec3(1.0, -2.0 + i, 1.5)));
  TagSpec mover = fixed_tag("mover", Vec3::Zero());
  mover.motion.kind = MotionSpec::Kind::kWaypoints;
  mover.motion.waypoints = {Vec3(0, -2, 1), Vec3(0, 2, 1)};
  mover.motion.speed_m_s = 0.3;
  mover.start_s = 1.0;
  s.tags.push_back(mover);
  return s;
}

bool same(const SimulationResult& a, const SimulationResult& b) {
  if (a.antennas.size() != b.antennas.size()) return false;
  for (size_t i = 0; i < a.antennas.size(); ++i) {
    const auto& x = a.antennas[i].reads;
    const auto& y = b.antennas[i].reads;
    if (x.size() != y.size()) return false;
    for (size_t k = 0; k < x.size(); ++k)
      if (x[k].tick != y[k].tick || x[k].tag != y[k].tag || x[k].reading.phase_rad != y[k].reading.phase_rad ||
          x[k].reading.rssi_dbm != y[k].reading.rssi_dbm || !(x[k].antenna_pose == y[k].antenna_pose) ||
          x[k].distance_m != y[k].distance_m || x[k].hop_index != y[k].hop_index)
        return false;
  }
  return true;
}

TEST(Simulation, TicksOrderAndDistancesOnAStaticScene) {
  Scenario s = static_scene();
  s.antennas[0].reader.range_m = 100.0;  // every tag always in range
  s.antennas[0].reader.noise_rssi = 0.0;
  const SimulationResult r = simulate(s, IdealChannel{});
  const AntennaResult& a = r.antennas[0];
  // 15 Hz over 2 s: ticks 0 … 30.
  EXPECT_EQ(a.ticks, 31u);
  EXPECT_EQ(a.attempts, 31u * 3u);
  ASSERT_EQ(a.reads.size(), 31u * 3u);
  const double expected_d[3] = {1.0, 2.0, 3.0};
  for (size_t k = 0; k < a.reads.size(); ++k) {
    const ReadRecord& rec = a.reads[k];
    EXPECT_EQ(rec.tick, k / 3);
    EXPECT_EQ(rec.tag, k % 3);
    EXPECT_NEAR(rec.time_s, (k / 3) / 15.0, 1e-12);
    EXPECT_NEAR(rec.distance_m, expected_d[k % 3], 1e-12);
    EXPECT_TRUE(rec.antenna_pose.position.isApprox(Vec3(0, 0, 1)));
    EXPECT_GE(rec.reading.phase_rad, 0.0);
    EXPECT_LT(rec.reading.phase_rad, kTwoPi);
  }
}

TEST(Simulation, IdenticalAtAnyThreadCountAndBlockSize) {
  for (ReaderModelKind model : {ReaderModelKind::kPaper, ReaderModelKind::kPhysical}) {
    Scenario s = robot_scene();
    for (AntennaSpec& a : s.antennas) a.reader.model = model;
    const SimulationResult one = simulate(s, IdealChannel{}, {1, 64});
    const SimulationResult two = simulate(s, IdealChannel{}, {2, 64});
    const SimulationResult small_blocks = simulate(s, IdealChannel{}, {2, 7});
    ASSERT_GT(one.antennas[0].reads.size(), 100u);
    EXPECT_TRUE(same(one, two));
    EXPECT_TRUE(same(one, small_blocks));
    Scenario other_seed = s;
    other_seed.seed = 2;
    EXPECT_FALSE(same(one, simulate(other_seed, IdealChannel{}, {2, 64})));
  }
}

TEST(Simulation, DurationDefaultsToRobotEndAndHoppingFollowsDwell) {
  const Scenario s = robot_scene();
  const SimulationResult r = simulate(s, IdealChannel{});
  const SceneMotion m = build_motion(s);
  EXPECT_DOUBLE_EQ(r.duration_s, m.robots[0]->end_time_s());
  EXPECT_EQ(r.antennas[0].ticks, static_cast<uint64_t>(std::floor(r.duration_s * 15.0 + 1e-9)) + 1);
  const ReaderParams& reader = s.antennas[0].reader;
  std::set<uint32_t> seen;
  for (const ReadRecord& rec : r.antennas[0].reads) {
    const size_t c = static_cast<size_t>(std::floor(rec.time_s / 0.4)) % 4;
    ASSERT_EQ(rec.hop_index, c);
    ASSERT_EQ(rec.frequency_hz, reader.frequencies_hz[c]);
    seen.insert(rec.hop_index);
    // The record carries the robot-mounted antenna pose at that time.
    ASSERT_TRUE(rec.antenna_pose.position.isApprox(m.antennas[0]->pose_at(rec.time_s).position));
  }
  EXPECT_EQ(seen.size(), 4u);
}

TEST(Simulation, TagsAndAntennasAppearAtTheirStartTimes) {
  Scenario s = robot_scene();
  s.antennas[1].start_s = 3.0;
  const SimulationResult r = simulate(s, IdealChannel{});
  const uint32_t mover = 5;
  bool mover_read = false;
  for (const auto& ant : r.antennas)
    for (const ReadRecord& rec : ant.reads)
      if (rec.tag == mover) {
        mover_read = true;
        EXPECT_GE(rec.time_s, 1.0);
      }
  EXPECT_TRUE(mover_read);
  ASSERT_FALSE(r.antennas[1].reads.empty());
  EXPECT_GE(r.antennas[1].reads.front().time_s, 3.0);
  EXPECT_EQ(r.antennas[1].ticks, static_cast<uint64_t>(std::floor(r.duration_s * 15.0 + 1e-9)) + 1 - 45);
}

TEST(Simulation, PhysicalModelGetsTheChannelPhase) {
  // Noise-free, unquantized physical model on the ideal channel: phase = φ0 + 4πD/λ (eq. 3), so h arrives
  // intact through the batch call and the cache.
  Scenario s = robot_scene();
  for (AntennaSpec& a : s.antennas) {
    a.reader.model = ReaderModelKind::kPhysical;
    a.reader.noise_phi_rad = 0.0;
    a.reader.noise_rssi_db = 0.0;
    a.reader.phase_bits = 0;
    a.reader.rssi_resolution_db = 0.0;
  }
  const SimulationResult r = simulate(s, IdealChannel{});
  size_t checked = 0;
  for (size_t a = 0; a < r.antennas.size(); ++a)
    for (const ReadRecord& rec : r.antennas[a].reads) {
      const double phi0 = s.antennas[a].reader.phase_offsets_rad[rec.hop_index];
      const double expected = wrap_to_2pi(phi0 + 4.0 * kPi * rec.distance_m / wavelength_m(rec.frequency_hz));
      // arg() of a product of rounded complex numbers: ~1e-12 rad relative to 4πD/λ ≈ 100 rad.
      ASSERT_NEAR(std::remainder(rec.reading.phase_rad - expected, kTwoPi), 0.0, 1e-9);
      ++checked;
    }
  EXPECT_GT(checked, 100u);
}

TEST(Simulation, StaticLinksAreComputedOncePerChannel) {
  Scenario s = static_scene();
  s.antennas[0].reader.model = ReaderModelKind::kPhysical;
  s.antennas[0].reader.frequencies_hz = {865.7e6, 866.3e6};
  s.antennas[0].reader.phase_offsets_rad = {0.0, 0.0};
  s.duration_s = 5.0;
  CountingChannel counting;
  const SimulationResult cached = simulate(s, counting, {2, 8});
  EXPECT_EQ(counting.links.load(), 3u * 2u);
  EXPECT_EQ(cached.channel_evaluations, 3u * 2u);
  // A channel that forbids caching is asked for every attempt, with the same result.
  CountingChannel uncached_channel(false);
  const SimulationResult uncached = simulate(s, uncached_channel, {2, 8});
  EXPECT_EQ(uncached_channel.links.load(), uncached.antennas[0].attempts);
  EXPECT_TRUE(same(cached, uncached));
}

TEST(Simulation, MovingLinksAreRecomputedAndReusedWhenTheRobotRests) {
  Scenario s = robot_scene();
  s.tags.pop_back();  // only static tags
  s.antennas.pop_back();
  s.antennas[0].reader.model = ReaderModelKind::kPhysical;
  s.antennas[0].reader.frequencies_hz = {865.7e6};
  s.antennas[0].reader.phase_offsets_rad = {0.0};
  const SceneMotion m = build_motion(s);
  const double end = m.robots[0]->end_time_s();
  s.duration_s = end + 10.0;  // the robot rests for the last 10 s
  CountingChannel counting;
  const SimulationOptions opts{1, 1000000};  // one block: the resting pose hits the cache every tick after
  const SimulationResult r = simulate(s, counting, opts);
  const uint64_t moving_ticks = static_cast<uint64_t>(std::floor(end * 15.0)) + 1;
  // Every tick while moving evaluates all 5 links; at rest only the first tick does.
  EXPECT_EQ(counting.links.load(), 5u * (moving_ticks + 1));
  CountingChannel uncached_channel(false);
  EXPECT_TRUE(same(r, simulate(s, uncached_channel, opts)));
}

TEST(Simulation, TagAtTheAntennaIsAnInputErrorNamingBoth) {
  Scenario s = static_scene();
  s.source = "scene.yaml";
  s.tags[1].source_line = 12;
  s.tags[1].motion.pose.position = Vec3(0, 0, 1);
  try {
    simulate(s, IdealChannel{});
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("scene.yaml:12"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'t1'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("'A'"), std::string::npos) << msg;
  }
  // Also for the physical model, whose static links are precomputed.
  s.antennas[0].reader.model = ReaderModelKind::kPhysical;
  EXPECT_THROW(simulate(s, IdealChannel{}, {2, 64}), InputError);
}

TEST(Simulation, DurationIsRequiredWhenNothingEndsTheRun) {
  Scenario s = static_scene();
  s.duration_s.reset();
  EXPECT_THROW(simulate(s, IdealChannel{}), InputError);
  s.duration_s = -1.0;
  EXPECT_THROW(simulate(s, IdealChannel{}), InputError);
}

TEST(Simulation, UnknownRobotIsAnInputError) {
  Scenario s = robot_scene();
  s.antennas[0].motion.robot = "rover";
  EXPECT_THROW(simulate(s, IdealChannel{}), InputError);
}

}  // namespace
}  // namespace rfidray
