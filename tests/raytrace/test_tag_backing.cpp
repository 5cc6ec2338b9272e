// A tag on a meshed metal plate and the same tag with the plate given as a backing (core/tag_couplings.h): the scene
// query finds the plate, and the two ways of describing it give the same reads — the image path is counted once
// (by the ray tracer when meshed, by the backing when not) and the detuning once.
#include <gtest/gtest.h>

#include <cmath>

#include "core/simulation.h"
#include "core/tag_couplings.h"
#include "core/units.h"
#include "raytrace/raytraced_channel.h"
#include "raytrace/warehouse.h"

namespace rfidray {
namespace {

constexpr double kF = 866e6;

TriangleMesh plane_mesh(const std::string& material, const Vec3& corner, const Vec3& u, const Vec3& v, int n) {
  TriangleMesh m;
  m.name = "plate";
  m.material_names = {material};
  add_quad(m, corner, u, v, 0, n, n);
  return m;
}

// A 4 m × 4 m plate in the plane x = 3 (x ≥ 3 behind it).
std::shared_ptr<const Scene> plate_scene(const std::string& material) {
  return std::make_shared<const Scene>(
      std::vector<TriangleMesh>{plane_mesh(material, Vec3(3, -2, -1), Vec3(0, 4, 0), Vec3(0, 0, 4), 8)},
      MaterialAssignment{});
}

TEST(TagBacking, NearestSurfaceIsThePlateWithItsMaterial) {
  const RaytracedChannel metal(plate_scene("metal"));
  const auto s = metal.nearest_surface(Vec3(2.99, 0.3, 1.2), 0.15);
  ASSERT_TRUE(s);
  EXPECT_NEAR(s->distance_m, 0.01, 1e-6);
  EXPECT_TRUE(s->material.perfect_conductor);
  EXPECT_EQ(s->material.name, "metal");
  EXPECT_TRUE(s->faces_facet);
  EXPECT_NEAR(s->facet_extent_m, 4.0, 1e-6);  // the plate is 4 m × 4 m: a plane to a 16.6 cm dipole
  // Off the plate's edge the nearest point is on the edge: (3, 2, 1.2) from (2.9, 2.1, 1.2) is √2·0.1 away.
  const auto e = metal.nearest_surface(Vec3(2.9, 2.1, 1.2), 0.5);
  ASSERT_TRUE(e);
  EXPECT_NEAR(e->distance_m, std::sqrt(0.02), 1e-6);
  EXPECT_FALSE(e->faces_facet);  // beyond the edge: the plane model does not describe it
  TagParams t;
  t.antenna.kind = TagAntennaSpec::Kind::kDipole;
  t.antenna.dipole = {0.166, 0.0005};
  TagBackingSpec beyond{TagBackingSpec::Kind::kScene, *builtin_material("metal"), e->distance_m, e->facet_extent_m, e->faces_facet};
  EXPECT_FALSE(plane_backing_ok(t, beyond));
  TagBackingSpec narrow{TagBackingSpec::Kind::kScene, *builtin_material("metal"), 0.01, 0.03, true};  // a 3 cm shelf edge
  EXPECT_FALSE(plane_backing_ok(t, narrow));
  TagBackingSpec wide{TagBackingSpec::Kind::kScene, *builtin_material("metal"), 0.01, 1.0, true};
  EXPECT_TRUE(plane_backing_ok(t, wide));
  EXPECT_FALSE(metal.nearest_surface(Vec3(2.5, 0, 1), 0.15));  // 0.5 m away: beyond the search radius
  const RaytracedChannel concrete(plate_scene("concrete"));
  const auto c = concrete.nearest_surface(Vec3(2.99, 0, 1), 0.15);
  ASSERT_TRUE(c);
  EXPECT_FALSE(c->material.perfect_conductor);
  EXPECT_FALSE(IdealChannel().nearest_surface(Vec3(2.99, 0, 1), 0.15));
}

Scenario one_link(const TagBackingSpec& backing, double gap_m) {
  Scenario s;
  AntennaSpec a;
  a.reader.name = "reader";
  a.reader.model = ReaderModelKind::kPhysical;
  a.reader.frequencies_hz = {kF};
  a.reader.phase_offsets_rad = {0.0};
  a.reader.noise_phi_rad = 0.0;
  a.reader.noise_rssi_db = 0.0;
  a.reader.rssi_resolution_db = 0.0;
  a.reader.phase_bits = 0;
  a.reader.sensitivity_dbm = -100.0;
  a.reader.tx_power_dbm = 40.0;
  a.reader.polarization.kind = PolarizationKind::kLinear;
  a.reader.polarization.axis_local = Vec3::UnitZ();
  a.motion.pose.position = Vec3(-17, 0, 1);  // 20 m from the tag, on the plate's normal
  s.antennas.push_back(a);
  TagSpec t;
  t.tag.name = "on_plate";
  t.tag.chip_sensitivity_dbm = -60.0;
  t.tag.polarization.kind = PolarizationKind::kLinear;
  t.tag.polarization.axis_local = Vec3::UnitZ();  // the dipole's wire, parallel to the plate
  t.tag.antenna.kind = TagAntennaSpec::Kind::kDipole;
  t.tag.antenna.dipole = {0.166, 0.0005};
  t.tag.backing = backing;
  // The tag faces the reader (its +X toward −X world); the plate is behind it, along its local −X.
  t.motion.pose.position = Vec3(3.0 - gap_m, 0, 1);
  t.motion.pose.orientation = Quat(Eigen::AngleAxisd(kPi, Vec3::UnitZ()));
  s.tags.push_back(t);
  s.duration_s = 0.0;
  return s;
}

Reading only_read(const Scenario& s, const Channel& ch) {
  const SimulationResult r = simulate(s, ch);
  EXPECT_EQ(r.antennas[0].reads.size(), 1u);
  return r.antennas[0].reads.empty() ? Reading{} : r.antennas[0].reads[0].reading;
}

TEST(TagBacking, MeshedPlateAndGivenBackingReadAlike) {
  for (double gap : {0.005, 0.01, 0.03}) {
    const RaytracedChannel meshed(plate_scene("metal"));
    const Reading on_mesh = only_read(one_link({TagBackingSpec::Kind::kScene, "", 0.0}, gap), meshed);
    const RaytracedChannel empty(std::make_shared<const Scene>(std::vector<TriangleMesh>{}, MaterialAssignment{}));
    const Reading given = only_read(one_link({TagBackingSpec::Kind::kGiven, *builtin_material("metal"), gap}, gap), empty);
    // The differences: the traced image path spreads as 1/(r + 2·gap) where the given backing's factor
    // 1 − e^{−j2kd} is the plane-wave limit, which turns the one-way phase by ~1/(kr) (0.003 rad at r = 20 m),
    // and the scene distance's 0.5 % solve grid: together well under 0.05 dB and 0.01 rad round trip.
    EXPECT_NEAR(on_mesh.rssi_dbm, given.rssi_dbm, 0.05) << "gap " << gap;
    EXPECT_NEAR(wrap_to_pi(on_mesh.phase_rad - given.phase_rad), 0.0, 0.01) << "gap " << gap;
    // Counting the plate twice (mesh and backing) would square the image factor |2 sin kd|²: −15 dB at 5 mm,
    // −9 dB at 1 cm (at 3 cm it is ≈ 1 and the test could not tell).
    if (gap < 0.02) {
      const SimulationResult twice = simulate(one_link({TagBackingSpec::Kind::kGiven, *builtin_material("metal"), gap}, gap), meshed);
      if (!twice.antennas[0].reads.empty())  // (no read at all differs too)
        EXPECT_GT(std::abs(twice.antennas[0].reads[0].reading.rssi_dbm - on_mesh.rssi_dbm), 10.0) << "gap " << gap;
    }
  }
}

TEST(TagBacking, DetuningChangesReadsOnlyWhenTheTagHasAnAntenna) {
  const RaytracedChannel meshed(plate_scene("metal"));
  Scenario point = one_link({}, 0.01);
  point.tags[0].tag.antenna = {};
  const Reading point_read = only_read(point, meshed);
  const Reading detuned = only_read(one_link({TagBackingSpec::Kind::kScene, "", 0.0}, 0.01), meshed);
  // The point tag sees only the image (|2 sin kd|² ≈ −8.9 dB one way); the dipole also its chip's mismatch and
  // its gain beside metal (F ≈ +5.7 dB one way, NEC-2 checked in tests/core/test_tag_antenna.cpp), and the
  // backscatter of its shorted state (K).
  EXPECT_GT(std::abs(detuned.rssi_dbm - point_read.rssi_dbm), 3.0);
  // Far from any surface a matched dipole reads as the point tag (F = 1, K = 1/4).
  Scenario far_point = one_link({}, 1.0), far_dipole = one_link({TagBackingSpec::Kind::kScene, "", 0.0}, 1.0);
  far_point.tags[0].tag.antenna = {};
  EXPECT_NEAR(only_read(far_point, meshed).rssi_dbm, only_read(far_dipole, meshed).rssi_dbm, 1e-9);
}

}  // namespace
}  // namespace rfidray
