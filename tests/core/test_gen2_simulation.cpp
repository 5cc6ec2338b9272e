// Gen2 readers in simulate(): one tag's read rate against the link formulas, session 2 persistence, ports and
// dwell, Select, determinism at any thread count, and the tick model left alone beside a Gen2 reader.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/error.h"
#include "core/gen2_simulation.h"
#include "core/simulation.h"
#include "tests/support/fixed_specs.h"

namespace rfidray {
namespace {

AntennaSpec antenna(const std::string& name, const Vec3& p) { return testing::fixed_antenna(name, p); }
TagSpec tag(const std::string& name, const Vec3& p) { return testing::fixed_tag(name, p); }

Gen2ReaderSpec gen2(int session, Gen2Target target, int q, Gen2QMode mode) {
  Gen2ReaderSpec g;
  g.link = *gen2_preset("max_throughput");
  g.session = session;
  g.target = target;
  g.q = q;
  g.q_mode = mode;
  return g;
}

// A Query→RN16→ACK→EPC cycle of the max-throughput profile from the formulas (test_gen2_link_timing.cpp):
// Query 277.0833 + T1 18.75 + RN16 35.9375 + T2 4.6875 + ACK 206.25 + T1 18.75 + EPC 210.9375 + T2 4.6875 µs.
constexpr double kMaxThroughputCycle_s = 777.0833333333e-6;

TEST(Gen2Simulation, OneTagFixedQ0DualTargetReadsOncePerCycle) {
  Scenario s;
  s.antennas.push_back(antenna("r", Vec3(0, 0, 1)));
  s.antennas[0].gen2 = gen2(0, Gen2Target::kAB, 0, Gen2QMode::kFixed);
  s.antennas[0].reader.noise_rssi = 0.0;  // eq. 5's noise can make a read fail; here every reply is decoded
  s.tags.push_back(tag("t", Vec3(2, 0, 1)));
  s.duration_s = 2.0;
  IdealChannel ch;
  const SimulationResult r = simulate(s, ch);
  const AntennaResult& a = r.antennas[0];
  ASSERT_TRUE(a.gen2);
  // Every round is one Query slot with one reply, read: reads = ⌊T / cycle⌋ (the last may end past T).
  const double expected = std::floor(2.0 / kMaxThroughputCycle_s);
  EXPECT_NEAR(double(a.reads.size()), expected, 1.0);
  EXPECT_EQ(a.gen2->single, a.gen2->slots());
  // Each row's time is the end of its EPC reply: cycle·k − T2 for the k-th read.
  ASSERT_GE(a.reads.size(), 2u);
  EXPECT_NEAR(a.reads[1].time_s - a.reads[0].time_s, kMaxThroughputCycle_s, 1e-9);
  EXPECT_NEAR(a.reads[0].time_s, kMaxThroughputCycle_s - 4.6875e-6, 1e-9);
  EXPECT_NEAR(a.reads[0].distance_m, 2.0, 1e-12);
}

TEST(Gen2Simulation, Session2TargetAReadsAStaticTagOnce) {
  Scenario s;
  s.antennas.push_back(antenna("r", Vec3(0, 0, 1)));
  s.antennas[0].gen2 = gen2(2, Gen2Target::kA, 4, Gen2QMode::kAdaptive);
  s.tags.push_back(tag("t", Vec3(2, 0, 1)));
  s.duration_s = 10.0;
  IdealChannel ch;
  const SimulationResult r = simulate(s, ch);
  EXPECT_EQ(r.antennas[0].reads.size(), 1u);
  // Session 0, target A: the flag also stays B while the tag is powered (no hop, no port switch).
  s.antennas[0].gen2->session = 0;
  EXPECT_EQ(simulate(s, ch).antennas[0].reads.size(), 1u);
  // Session 1: the flag reverts after s1_persistence_s (2 s), so the tag is read again every ~2 s.
  s.antennas[0].gen2->session = 1;
  const size_t s1 = simulate(s, ch).antennas[0].reads.size();
  EXPECT_GE(s1, 4u);
  EXPECT_LE(s1, 5u);
}

// Two ports: `near` powers the tag, `far` (20 m, beyond the 7 m range) does not. Session 2, target A: while the
// reader dwells on `far` the tag is unpowered; when that lasts longer than s23_persistence_s (2.5 s here) its flag
// persists out and `near` reads it again on its next dwell; a shorter absence keeps it B.
TEST(Gen2Simulation, Session2FlagPersistsOutAcrossPorts) {
  auto run = [](double far_dwell_s, int session) {
    Scenario s;
    s.antennas.push_back(antenna("near", Vec3(0, 0, 1)));
    s.antennas.push_back(antenna("far", Vec3(30, 0, 1)));
    Gen2ReaderSpec g = gen2(session, Gen2Target::kA, 2, Gen2QMode::kAdaptive);
    g.s23_persistence_s = 2.5;
    g.ports = {{0, "near", 0.5}, {1, "far", far_dwell_s}};
    s.antennas[0].gen2 = g;
    s.tags.push_back(tag("t", Vec3(2, 0, 1)));
    s.duration_s = 20.0;
    IdealChannel ch;
    const SimulationResult r = simulate(s, ch);
    EXPECT_TRUE(r.antennas[1].reads.empty());
    EXPECT_TRUE(r.antennas[1].gen2.has_value());
    return r.antennas[0].reads.size();
  };
  // 3.5 s cycles: near dwells start at 0, 3.5, 7, …, 17.5 (6 dwells), each reads the tag once.
  EXPECT_EQ(run(3.0, 2), 6u);
  // 1.5 s cycles: 1 s away < 2.5 s: read once.
  EXPECT_EQ(run(1.0, 2), 1u);
  // Session 0 has no persistence across a port switch: once per near dwell (20 / 1.5 → 14 dwells).
  EXPECT_EQ(run(1.0, 0), 14u);
}

TEST(Gen2Simulation, SelectReadsOnlyThePopulation) {
  Scenario s;
  s.antennas.push_back(antenna("r", Vec3(0, 0, 1)));
  s.antennas[0].gen2 = gen2(0, Gen2Target::kAB, 2, Gen2QMode::kAdaptive);
  s.antennas[0].gen2->select_prefix = "pallet";
  s.tags.push_back(tag("pallet1", Vec3(2, 0, 1)));
  s.tags.push_back(tag("shelf1", Vec3(2, 1, 1)));
  s.tags.push_back(tag("pallet2", Vec3(2, -1, 1)));
  s.duration_s = 0.5;
  IdealChannel ch;
  const SimulationResult r = simulate(s, ch);
  size_t per_tag[3] = {0, 0, 0};
  for (const ReadRecord& rec : r.antennas[0].reads) ++per_tag[rec.tag];
  EXPECT_GT(per_tag[0], 50u);
  EXPECT_EQ(per_tag[1], 0u);
  EXPECT_GT(per_tag[2], 50u);
}

TEST(Gen2Simulation, PhysicalModelPowerDecidesAndThreadsDoNotChangeReads) {
  Scenario s;
  s.antennas.push_back(antenna("r1", Vec3(0, 0, 1)));
  s.antennas.push_back(antenna("r2", Vec3(6, 0, 1)));
  s.antennas.push_back(antenna("ticks", Vec3(3, 3, 1)));
  for (AntennaSpec& a : s.antennas) a.reader.model = ReaderModelKind::kPhysical;
  s.antennas[0].gen2 = gen2(1, Gen2Target::kAB, 4, Gen2QMode::kAdaptive);
  s.antennas[1].gen2 = gen2(0, Gen2Target::kA, 3, Gen2QMode::kFixed);
  s.antennas[1].gen2->link = *gen2_preset("dense_reader_m4");
  s.antennas[0].reader.frequencies_hz = {865.7e6, 866.3e6};
  s.antennas[0].reader.phase_offsets_rad = {0.0, 0.3};
  s.antennas[0].reader.hop_dwell_s = 0.2;
  for (int i = 0; i < 40; ++i) s.tags.push_back(tag("t" + std::to_string(i), Vec3(0.3 * i, 0.5, 1)));
  s.duration_s = 1.0;
  IdealChannel ch;
  SimulationOptions one, two;
  one.threads = 1;
  two.threads = 2;
  const SimulationResult a = simulate(s, ch, one), b = simulate(s, ch, two);
  for (size_t k = 0; k < 3; ++k) {
    ASSERT_EQ(a.antennas[k].reads.size(), b.antennas[k].reads.size());
    for (size_t i = 0; i < a.antennas[k].reads.size(); ++i) {
      EXPECT_EQ(a.antennas[k].reads[i].tag, b.antennas[k].reads[i].tag);
      EXPECT_EQ(a.antennas[k].reads[i].time_s, b.antennas[k].reads[i].time_s);
      EXPECT_EQ(a.antennas[k].reads[i].reading.phase_rad, b.antennas[k].reads[i].reading.phase_rad);
    }
  }
  // The tick antenna keeps ticking at 15 Hz (16 ticks in 1 s), the Gen2 ones do not.
  EXPECT_EQ(a.antennas[2].ticks, 16u);
  EXPECT_FALSE(a.antennas[2].gen2.has_value());
  ASSERT_TRUE(a.antennas[0].gen2.has_value());
  // Hopping: reads on both carriers; every read's tag is within the physical model's reach (−20 dBm chip at
  // 30 dBm EIRP, isotropic: D ≤ λ/(4π)·10^(50/20) = 8.71 m at 865.7 MHz).
  bool hop[2] = {false, false};
  for (const ReadRecord& rec : a.antennas[0].reads) {
    hop[rec.hop_index] = true;
    EXPECT_LE(rec.distance_m, 8.72);
  }
  EXPECT_TRUE(hop[0] && hop[1]);
  // Tags beyond reach are never read.
  for (const ReadRecord& rec : a.antennas[1].reads) EXPECT_LE(rec.distance_m, 8.72);
}

TEST(Gen2Simulation, BadPortsAreInputErrors) {
  Scenario s;
  s.source = "scene.yaml";
  s.antennas.push_back(antenna("a", Vec3(0, 0, 1)));
  s.antennas.push_back(antenna("b", Vec3(1, 0, 1)));
  s.antennas[0].source_line = 7;
  s.antennas[0].gen2 = gen2(0, Gen2Target::kA, 2, Gen2QMode::kFixed);
  s.antennas[0].gen2->ports = {{1, "b", 0.1}, {0, "a", 0.1}};
  s.antennas[1].reader.frequencies_hz = {866.9e6};
  s.duration_s = 1.0;
  IdealChannel ch;
  try {
    simulate(s, ch);
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene.yaml:7: field 'antennas[0].gen2.ports'"), std::string::npos) << e.what();
  }
  s.antennas[1].reader.frequencies_hz = {865.7e6};
  s.antennas[0].gen2->session = 4;
  EXPECT_THROW(simulate(s, ch), InputError);
}

}  // namespace
}  // namespace rfidray
