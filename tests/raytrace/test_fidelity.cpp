// channel: auto (raytrace/fidelity.h): the ladder picks the reference level at zero tolerance, the ideal
// channel on an empty scene, and stops at los+blocked where nothing can reflect; link caching in the simulation
// loop gives the same readings as recomputing every link with the ray-traced channel.
#include <gtest/gtest.h>

#include <atomic>
#include <limits>
#include <string>

#include "core/level_validity.h"
#include "core/reader_model.h"
#include "core/simulation.h"
#include "raytrace/fidelity.h"
#include "raytrace/raytraced_channel.h"
#include "tests/support/endpoint_at.h"
#include "raytrace/warehouse.h"

namespace rfidray {
namespace {

constexpr double kF = 865.7e6;


// One batch per antenna position, every tag in each, with the default reader's and tag's readability.
std::vector<LinkBatch> batches(const std::vector<Vec3>& antennas, const std::vector<Vec3>& tags) {
  std::vector<LinkBatch> out;
  const double min_h2 = min_readable_h2(ReaderParams{}, TagParams{});
  for (size_t a = 0; a < antennas.size(); ++a) {
    LinkBatch b;
    b.antenna = 0;
    b.frequency_hz = kF;
    b.antenna_end = testing::endpoint_at(antennas[a]);
    for (size_t i = 0; i < tags.size(); ++i) {
      b.tags.push_back(i);
      b.tag_ends.push_back(testing::endpoint_at(tags[i]));
      b.min_readable_h2.push_back(min_h2);
    }
    out.push_back(b);
  }
  return out;
}

std::vector<Vec3> paper_tags() {
  return {{2.90, 0.57, 2.05},  {2.90, -1.24, 2.05}, {2.90, -3.03, 2.05}, {2.90, -4.82, 2.05}, {2.90, -6.75, 2.05},
          {2.90, -8.66, 2.05}, {-4.85, -7.70, 1.85}, {-4.85, -3.03, 1.85}, {-4.85, 1.44, 1.85}, {-4.85, 5.95, 1.85}};
}

std::vector<Vec3> aisle_poses(int n) {
  std::vector<Vec3> out;
  for (int k = 0; k < n; ++k) out.emplace_back(-1.0, -10.0 + 18.0 * k / (n - 1), 1.68);
  return out;
}

// auto's reference is judged too: the paper's tags sit 7 cm from the racks' shelf edges, across them (a vertical
// tag and horizontal edges) and beside a second edge, where full is not checked (core/level_validity.h); tags in
// the open, on links that pass no edge's end, are not flagged.
TEST(Fidelity, CountsSampledLinksWhereTheReferenceIsOutsideItsValidity) {
  const auto scene = std::make_shared<const Scene>(paper_warehouse_meshes(), MaterialAssignment{});
  const FidelityChoice near_racks = choose_fidelity(scene, batches(aisle_poses(4), paper_tags()), TraceOptions{},
                                                    {0.05, 0.5});
  EXPECT_EQ(near_racks.links_outside_validity, near_racks.links);
  EXPECT_NE(near_racks.reason.find("outside"), std::string::npos) << near_racks.reason;
  // (Not every open tag: a link 13 m along the aisle to (−1, 3, 1.2) passes a rack's edge within a Fresnel zone of
  // the edge's end, which the edge-end check flags, raytrace/edge_end_finder.h.)
  const FidelityChoice open = choose_fidelity(scene, batches(aisle_poses(4), {{-1.0, -2.0, 1.0}, {-1.0, -6.0, 1.1}}),
                                              TraceOptions{}, {0.05, 0.5});
  EXPECT_EQ(open.links_outside_validity, 0u) << open.reason;
}

TEST(Fidelity, ZeroToleranceKeepsTheReferenceLevel) {
  const auto scene = std::make_shared<const Scene>(paper_warehouse_meshes(), MaterialAssignment{});
  const auto sample = batches(aisle_poses(12), paper_tags());
  const FidelityChoice c = choose_fidelity(scene, sample, TraceOptions{}, {0.0, 0.0});
  EXPECT_NE(c.picked.level, ChannelLevel::kIdeal);
  EXPECT_EQ(c.picked.options.level, ChannelLevel::kFull);
  EXPECT_EQ(c.links, 120u);
  // Every cheaper rung was tried and rejected; the reference row has no error.
  ASSERT_GE(c.rows.size(), 4u);
  for (size_t i = 0; i + 1 < c.rows.size(); ++i) EXPECT_FALSE(c.rows[i].within) << c.rows[i].rung.label;
  EXPECT_EQ(c.rows.back().errors.phase_p95_rad, 0.0);
  EXPECT_EQ(c.rows.back().errors.rssi_p95_db, 0.0);
  // The racks and the floor matter in this warehouse: the free-space rung is far outside the default tolerance.
  EXPECT_GT(c.rows.front().errors.phase_p95_rad, 0.05);
}

TEST(Fidelity, EmptySceneIsTheIdealChannel) {
  const auto scene = std::make_shared<const Scene>(std::vector<TriangleMesh>{}, MaterialAssignment{});
  const auto sample = batches(aisle_poses(5), paper_tags());
  const FidelityChoice c = choose_fidelity(scene, sample, TraceOptions{}, FidelityTolerance{});
  EXPECT_EQ(c.picked.level, ChannelLevel::kIdeal);
  ASSERT_EQ(c.rows.size(), 1u);  // the first rung passes: nothing else is evaluated against it
  EXPECT_EQ(c.rows[0].rays_per_link, 0.0);
  const auto channel = make_rung_channel(scene, c.picked);
  EXPECT_EQ(channel->name(), "ideal");
}

TEST(Fidelity, WhereNothingCanReflectItStopsAtLosPlusBlocked) {
  // A concrete wall sheet x = 0, y −50…50, z −50…50; antennas at x < 0, tags at x > 0: no specular reflection
  // is possible (the two ends are on opposite sides of the only plane), every link crosses the wall, and the
  // wall's edges are ~50 m away (their diffraction, in the reference, is ~1e-3 of the field).
  TriangleMesh wall;
  wall.name = "wall";
  wall.material_names = {"concrete"};
  add_quad(wall, Vec3(0, -50, -50), Vec3(0, 100, 0), Vec3(0, 0, 100), 0);
  const auto scene = std::make_shared<const Scene>(std::vector<TriangleMesh>{wall}, MaterialAssignment{});
  const auto sample = batches({{-2, -1, 1.5}, {-2, 3, 1.5}}, {{2, 0, 1.5}, {2, 1, 1.2}, {2, 4, 1.5}, {2, -4, 1.0}});
  const FidelityChoice c = choose_fidelity(scene, sample, TraceOptions{}, FidelityTolerance{});
  EXPECT_EQ(c.picked.label, "los+blocked");
  ASSERT_EQ(c.rows.size(), 3u);
  EXPECT_FALSE(c.rows[0].within);                     // ideal ignores the wall's loss
  EXPECT_GT(c.rows[1].errors.status_mismatches, 0u);  // los loses the links through the wall
  EXPECT_LT(c.rows[2].errors.phase_p95_rad, 0.01);    // los+blocked misses only the far edges' diffraction
}

// Forwards to a channel but forbids caching, so the simulation recomputes every link every tick.
class Uncached final : public Channel {
 public:
  explicit Uncached(const Channel& inner) : inner_(inner) {}
  std::string name() const override { return inner_.name(); }
  std::vector<Path> paths(const Endpoint& a, const Endpoint& t, double f) const override { return inner_.paths(a, t, f); }
  void one_way(const Endpoint& a, std::span<const Endpoint> tags, double f,
               std::span<std::complex<double>> h) const override {
    inner_.one_way(a, tags, f, h);
  }
  bool cacheable() const override { return false; }

 private:
  const Channel& inner_;
};

// The paper warehouse's fixed antenna (physical reader model) and tags "tag1"… at `tags`; a test adds its second
// antenna (a copy of the first, renamed and moved).
Scenario fixed_antenna_scenario(double duration_s, const std::vector<Vec3>& tags) {
  Scenario s;
  s.duration_s = duration_s;
  AntennaSpec fixed;
  fixed.reader.name = "fixed";
  fixed.reader.model = ReaderModelKind::kPhysical;
  fixed.motion.pose.position = Vec3(3.5, -4.0, 2.0);
  s.antennas.push_back(fixed);
  for (size_t i = 0; i < tags.size(); ++i) {
    TagSpec t;
    t.tag.name = "tag" + std::to_string(i + 1);
    t.motion.pose.position = tags[i];
    s.tags.push_back(t);
  }
  return s;
}

// Expects the same reads (tick, tag, phase and RSSI to the bit) from both runs; returns how many were compared.
size_t same_reads(const SimulationResult& a, const SimulationResult& b) {
  size_t reads = 0;
  EXPECT_EQ(a.antennas.size(), b.antennas.size());
  for (size_t k = 0; k < std::min(a.antennas.size(), b.antennas.size()); ++k) {
    EXPECT_EQ(a.antennas[k].reads.size(), b.antennas[k].reads.size()) << "antenna " << k;
    for (size_t r = 0; r < std::min(a.antennas[k].reads.size(), b.antennas[k].reads.size()); ++r) {
      const ReadRecord &x = a.antennas[k].reads[r], &y = b.antennas[k].reads[r];
      EXPECT_EQ(x.tick, y.tick);
      EXPECT_EQ(x.tag, y.tag);
      EXPECT_EQ(x.reading.phase_rad, y.reading.phase_rad);
      EXPECT_EQ(x.reading.rssi_dbm, y.reading.rssi_dbm);
      ++reads;
    }
  }
  return reads;
}

TEST(Fidelity, CachedAndRecomputedRaytracedLinksGiveIdenticalReadings) {
  // The mover stops at t = 2 s and rests: its links hit the cache from then on.
  Scenario s = fixed_antenna_scenario(6.0, paper_tags());
  AntennaSpec mover = s.antennas[0];
  mover.reader.name = "mover";
  mover.motion.kind = MotionSpec::Kind::kWaypoints;
  mover.motion.waypoints = {Vec3(-1, -5, 1.68), Vec3(-1, -4, 1.68)};
  mover.motion.speed_m_s = 0.5;
  s.antennas.push_back(mover);
  const auto scene = std::make_shared<const Scene>(paper_warehouse_meshes(), MaterialAssignment{});
  const RaytracedChannel traced(scene);
  const Uncached uncached(traced);
  const SimulationResult a = simulate(s, traced, {2, 16});
  const SimulationResult b = simulate(s, uncached, {2, 16});
  EXPECT_LT(a.channel_evaluations, b.channel_evaluations / 2);
  EXPECT_GT(same_reads(a, b), 500u);
}

// simulate judges every tag's links at the start poses (core/simulation.cpp, in parallel since 2026-12-06): the
// count and the note naming the worst tag are those of a serial pass over the tags, at one thread and at two.
TEST(Fidelity, StaticLinksSplitOverThreadsGiveTheSameReadsAsOneThread) {
  // 24 static tags at full: from double-bounce up one_way splits as few as 17 tags over the threads, so with the
  // default thread count simulate computes its static links one job at a time on every thread; with one thread
  // serially. The reads must be identical.
  std::vector<Vec3> tags;
  for (double y = -8.0; y <= 3.5; y += 0.5) tags.push_back({2.90, y, 1.1});
  Scenario s = fixed_antenna_scenario(0.5, tags);
  const auto scene = std::make_shared<const Scene>(paper_warehouse_meshes(), MaterialAssignment{});
  TraceOptions o;
  o.level = ChannelLevel::kFull;
  const RaytracedChannel full(scene, o);
  ASSERT_LE(full.threaded_batch_min_tags(), tags.size());
  const SimulationResult one = simulate(s, full, {1, 64});
  const SimulationResult every = simulate(s, full, {0, 64});
  EXPECT_GT(same_reads(one, every), 10u);
}

TEST(Fidelity, SimulateCountsTagsOutsideValidityAsASerialPassDoesAtAnyThreadCount) {
  std::vector<Vec3> tags = paper_tags();
  tags.push_back({-1.0, -2.0, 1.0});  // in the open
  tags.push_back({-1.0, -6.0, 1.1});
  Scenario s = fixed_antenna_scenario(0.2, tags);
  AntennaSpec aisle = s.antennas[0];
  aisle.reader.name = "aisle";
  aisle.motion.pose.position = Vec3(-1.0, -5.0, 1.68);
  s.antennas.push_back(aisle);
  const auto scene = std::make_shared<const Scene>(paper_warehouse_meshes(), MaterialAssignment{});
  TraceOptions o;
  o.level = ChannelLevel::kFull;
  const RaytracedChannel full(scene, o);
  size_t expected = 0, worst = 0;
  double worst_error = -1.0;
  for (size_t i = 0; i < tags.size(); ++i) {
    LevelValidity v;
    for (size_t a = 0; a < s.antennas.size(); ++a) {
      // The ends as simulate makes them: the reader's and the tag's pattern and polarization at the start poses.
      const ReaderParams& r = s.antennas[a].reader;
      const Endpoint antenna{s.antennas[a].motion.pose, r.pattern, r.polarization};
      const Endpoint tag{s.tags[i].motion.pose, s.tags[i].tag.pattern, s.tags[i].tag.polarization};
      const double f = r.frequencies_hz.front();
      const LevelValidity va = level_validity(ChannelLevel::kFull, link_sight(full, antenna, tag, f), f);
      if (a == 0 || (!va.level_ok && (v.level_ok || va.estimated_error > v.estimated_error))) v = va;
    }
    if (v.level_ok) continue;
    if (expected++ == 0 || v.estimated_error > worst_error) worst = i, worst_error = v.estimated_error;
  }
  ASSERT_GT(expected, 0u);
  EXPECT_LT(expected, tags.size());  // the open tags pass
  const SimulationResult one = simulate(s, full, {1, 16});
  const SimulationResult two = simulate(s, full, {2, 16});
  EXPECT_EQ(one.tags_outside_validity, expected);
  EXPECT_EQ(two.tags_outside_validity, expected);
  EXPECT_EQ(one.notes, two.notes);
  const std::string named = "the worst, tag '" + s.tags[worst].tag.name + "'";
  ASSERT_FALSE(two.notes.empty());
  EXPECT_NE(two.notes.back().find(named), std::string::npos) << two.notes.back();
}

// A rung whose links flip readability has an unbounded p95 (core/channel_error.h): the table says "flips" and why,
// never "inf"; a finite p95 is printed as a number.
TEST(Fidelity, TableNamesFlipsInsteadOfPrintingInfinity) {
  FidelityChoice c;
  FidelityRow flipping, finite;
  flipping.rung.label = "los";
  flipping.errors.links = 20;
  flipping.errors.status_mismatches = 3;
  flipping.errors.phase_p95_rad = std::numeric_limits<double>::infinity();
  flipping.errors.rssi_p95_db = std::numeric_limits<double>::infinity();
  finite.rung.label = "full";
  finite.errors.links = 20;
  finite.errors.phase_p95_rad = 0.0123;
  finite.errors.rssi_p95_db = 0.25;
  finite.within = true;
  c.rows = {flipping, finite};
  c.picked = finite.rung;
  std::string all;
  for (const std::string& line : describe(c)) all += line + "\n";
  EXPECT_EQ(all.find("inf"), std::string::npos) << all;
  EXPECT_NE(all.find("flips"), std::string::npos) << all;
  EXPECT_NE(all.find("unbounded"), std::string::npos) << all;
  EXPECT_NE(all.find("0.0123"), std::string::npos) << all;
  c.rows = {finite};  // no flips: no explanation line
  all.clear();
  for (const std::string& line : describe(c)) all += line + "\n";
  EXPECT_EQ(all.find("unbounded"), std::string::npos) << all;
}

}  // namespace
}  // namespace rfidray

namespace rfidray {
namespace {

TEST(Fidelity, LadderAddsCandidateRaysOnlyWhereTheyPayOff) {
  auto labels = [](const std::vector<FidelityRung>& l) {
    std::vector<std::string> out;
    for (const auto& r : l) out.push_back(r.label);
    return out;
  };
  const std::vector<std::string> few = labels(fidelity_ladder(TraceOptions{}, 10.0));
  EXPECT_EQ(few, (std::vector<std::string>{"ideal", "los", "los+blocked", "single-bounce", "double-bounce",
                                           "full-selective", "full",
                                           "full exhaustive"}));
  const auto many = fidelity_ladder(TraceOptions{}, 5000.0);
  ASSERT_EQ(many.size(), 9u);
  EXPECT_EQ(many[3].label, "single-bounce rays=4096");
  EXPECT_EQ(many[3].options.candidate_rays, 4096);
  TraceOptions user;
  user.candidate_rays = 1000;
  EXPECT_EQ(fidelity_ladder(user, 10.0)[3].options.candidate_rays, 1000);  // the user's setting, always
  EXPECT_EQ(fidelity_ladder(user, 10.0).back().options.candidates, CandidateMode::kExhaustive);
}

}  // namespace
}  // namespace rfidray
