// Level double-bounce (raytrace/double_bounce.cpp) against image theory: a corner of two perpendicular metal
// walls and two parallel metal walls (image positions, path lengths, reflection points and coefficients to
// 1e-9), the exact candidate search against the exhaustive one on the paper warehouse, and the plane pairs
// shared by a block of tags (PathFinder::plane_pairs_near) against every pair per link.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "core/units.h"
#include "raytrace/raytraced_channel.h"
#include "raytrace/warehouse.h"
#include "tests/support/endpoint_at.h"

namespace rfidray {
namespace {

using C = std::complex<double>;
constexpr double kF = 866e6;

using testing::linear_dipole_at;

TriangleMesh quad(const std::string& name, const Vec3& corner, const Vec3& u, const Vec3& v) {
  TriangleMesh m;
  m.name = name;
  m.material_names = {"metal"};
  add_quad(m, corner, u, v, 0, 1, 1);
  return m;
}

TraceOptions level_options(ChannelLevel level, CandidateMode mode) {
  TraceOptions o;
  o.level = level;
  o.candidates = mode;
  o.drop_below_db = 400.0;  // keep every path: the closed forms include them all
  return o;
}

// The image of a current element in a perfectly conducting plane with unit normal n: tangential part reversed,
// normal part kept, i.e. −(mirror of the vector) (image theory).
Vec3 pec_image(const Vec3& current, const Vec3& n) { return -(current - 2.0 * current.dot(n) * n); }
Vec3 mirror_point(const Vec3& p, const Vec3& n, double c) { return p - 2.0 * (n.dot(p) - c) * n; }

// Expected coefficient of a double reflection on metal: the field the doubly imaged antenna (axis a21, at the
// image point) radiates towards the tag, matched against the tag. Both ends isotropic.
C image_coefficient(const Vec3& a21, const Vec3& image, const Endpoint& tag) {
  const Vec3 d = (tag.pose.position - image).normalized();
  Polarization p;
  p.axis_local = a21.normalized();
  return polarization_match(p.field(Quat::Identity(), d), tag.polarization, tag.pose.orientation, d);
}

struct Expected {
  Vec3 image, p1, p2;
  C coefficient;
};

// Two reflections, first in plane (n1, c1), then (n2, c2), by image theory.
Expected expected_double(const Endpoint& a, const Endpoint& t, const Vec3& n1, double c1, const Vec3& n2, double c2) {
  Expected e;
  const Vec3 t2 = mirror_point(t.pose.position, n2, c2);
  e.image = mirror_point(t2, n1, c1);
  const Vec3& pa = a.pose.position;
  const double s1 = (c1 - n1.dot(pa)) / n1.dot(e.image - pa);
  e.p1 = pa + s1 * (e.image - pa);
  const double s2 = (c2 - n2.dot(e.p1)) / n2.dot(t2 - e.p1);
  e.p2 = e.p1 + s2 * (t2 - e.p1);
  // The antenna imaged in plane 1, then in plane 2, sits at the mirror of the tag's double image as seen from
  // the tag; equivalently (reciprocity) the source's image axis is pec_image(pec_image(axis, n1), n2).
  const Vec3 axis = pec_image(pec_image(a.polarization.axis_local, n1), n2);
  // The doubly imaged antenna stands at A21 = mirror(mirror(A, n1), n2) and radiates straight to T.
  const Vec3 a21 = mirror_point(mirror_point(pa, n1, c1), n2, c2);
  e.coefficient = image_coefficient(axis, a21, t);
  return e;
}

void expect_path(const Path& p, PathKind kind, const Expected& e, const Endpoint& a) {
  EXPECT_EQ(p.kind, kind);
  EXPECT_NEAR(p.length_m, (e.image - a.pose.position).norm(), 1e-9);
  EXPECT_LT((p.point - e.p1).norm(), 1e-9);
  EXPECT_LT((p.point2 - e.p2).norm(), 1e-9);
  EXPECT_LT(std::abs(p.coefficient - e.coefficient), 1e-9) << p.coefficient << " vs " << e.coefficient;
  EXPECT_EQ(p.material, "metal");
  EXPECT_EQ(p.material2, "metal");
}

TEST(DoubleBounce, CornerOfTwoPerpendicularMetalWallsMatchesImageTheory) {
  // Walls x = 0 (y 0…50) and y = 0 (x 0…50), z −50…50; antenna and tag in the quadrant x, y > 0.
  const auto scene = std::make_shared<const Scene>(
      std::vector<TriangleMesh>{quad("wx", Vec3(0, 0, -50), Vec3(0, 50, 0), Vec3(0, 0, 100)),
                                quad("wy", Vec3(0, 0, -50), Vec3(50, 0, 0), Vec3(0, 0, 100))},
      MaterialAssignment{});
  const Vec3 nx = Vec3::UnitX(), ny = Vec3::UnitY();
  for (CandidateMode mode : {CandidateMode::kExact, CandidateMode::kExhaustive}) {
    const RaytracedChannel ch(scene, level_options(ChannelLevel::kDoubleBounce, mode));
    for (const Vec3& axis : {Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0.3, -0.5, 0.8)})
      for (const auto& [pa, pt] : {std::pair{Vec3(1.0, 2.5, 1.2), Vec3(3.0, 0.7, 1.9)},
                                   std::pair{Vec3(4.0, 1.0, 0.5), Vec3(0.8, 3.1, 2.2)},
                                   std::pair{Vec3(2.0, 2.0, 1.0), Vec3(2.5, 1.5, 1.0)}}) {
        const Endpoint a = linear_dipole_at(pa, axis), t = linear_dipole_at(pt, axis);
        const auto paths = ch.paths(a, t, kF);
        // LoS, the two single reflections, and exactly one double reflection: the line from A to the double
        // image (−tx, −ty) crosses one wall first, which fixes the order.
        ASSERT_EQ(paths.size(), 4u) << to_string(mode);
        const Path& d = paths[3];
        ASSERT_EQ(d.kind, PathKind::kReflection2);
        const Expected xy = expected_double(a, t, nx, 0.0, ny, 0.0), yx = expected_double(a, t, ny, 0.0, nx, 0.0);
        EXPECT_LT((xy.image - yx.image).norm(), 1e-12);  // the same image point either way
        const bool x_first = std::abs(d.point.x()) < 1e-9;
        expect_path(d, PathKind::kReflection2, x_first ? xy : yx, a);
        // Which wall comes first: the one the line A → image crosses first.
        const Vec3 image = xy.image;
        const double sx = pa.x() / (pa.x() - image.x()), sy = pa.y() / (pa.y() - image.y());
        EXPECT_EQ(x_first, sx < sy);
        // Vertical polarization on vertical walls: TE twice, (−1)(−1) = +1.
        if (axis == Vec3(0, 0, 1)) {
          EXPECT_LT(std::abs(d.coefficient - 1.0), 1e-9);
        }
        // The double reflection is the only new path: single-bounce gives the other three unchanged.
        const auto single = RaytracedChannel(scene, level_options(ChannelLevel::kSingleBounce, mode)).paths(a, t, kF);
        ASSERT_EQ(single.size(), 3u);
        for (size_t i = 0; i < 3; ++i) EXPECT_EQ(single[i].contribution, paths[i].contribution);
      }
  }
}

TEST(DoubleBounce, TwoParallelMetalWallsGiveBothImageOrders) {
  // Walls x = 0 and x = 4 (y −50…50, z −50…50); antenna and tag between them.
  const double w = 4.0;
  const auto scene = std::make_shared<const Scene>(
      std::vector<TriangleMesh>{quad("w0", Vec3(0, -50, -50), Vec3(0, 100, 0), Vec3(0, 0, 100)),
                                quad("w4", Vec3(w, -50, -50), Vec3(0, 0, 100), Vec3(0, 100, 0))},
      MaterialAssignment{});
  const Vec3 n = Vec3::UnitX();
  for (CandidateMode mode : {CandidateMode::kExact, CandidateMode::kExhaustive}) {
    const RaytracedChannel ch(scene, level_options(ChannelLevel::kDoubleBounce, mode));
    for (const Vec3& axis : {Vec3(0, 0, 1), Vec3(1, 0, 0), Vec3(0.6, 0.2, -0.5)}) {
      const Endpoint a = linear_dipole_at(Vec3(1.0, -2.0, 1.0), axis), t = linear_dipole_at(Vec3(2.7, 3.5, 1.6), axis);
      const auto paths = ch.paths(a, t, kF);
      ASSERT_EQ(paths.size(), 5u);  // LoS, two single reflections, two double reflections
      const Expected first0 = expected_double(a, t, n, 0.0, n, w);  // x = 0 first, then x = 4
      const Expected first4 = expected_double(a, t, n, w, n, 0.0);
      // Images: T at x = 2.7 → x = 4: 5.3 → x = 0: −5.3;  x = 0: −2.7 → x = 4: 10.7.
      EXPECT_NEAR(first0.image.x(), -5.3, 1e-12);
      EXPECT_NEAR(first4.image.x(), 10.7, 1e-12);
      std::vector<const Path*> doubles;
      for (const Path& p : paths)
        if (p.kind == PathKind::kReflection2) doubles.push_back(&p);
      ASSERT_EQ(doubles.size(), 2u);
      // Ordered by length: |A − (−5.3, …)| < |A − (10.7, …)| here.
      expect_path(*doubles[0], PathKind::kReflection2, first0, a);
      expect_path(*doubles[1], PathKind::kReflection2, first4, a);
      if (axis == Vec3(0, 0, 1)) {
        EXPECT_LT(std::abs(doubles[0]->coefficient - 1.0), 1e-9);
        EXPECT_LT(std::abs(doubles[1]->coefficient - 1.0), 1e-9);
      }
      // h is the closed-form sum of the five image sources.
      C expected_h = path_contribution((t.pose.position - a.pose.position).norm(), paths[0].coefficient, kF);
      for (const Path& p : paths)
        if (p.kind != PathKind::kLineOfSight) expected_h += path_contribution(p.length_m, p.coefficient, kF);
      EXPECT_LT(std::abs(sum_paths(paths) - expected_h), 1e-9 * std::abs(expected_h));
    }
  }
}

std::vector<Endpoint> paper_tags() {
  std::vector<Endpoint> tags;
  for (double y : {0.57, -1.24, -3.03, -4.82, -6.75, -8.66})
    tags.push_back(linear_dipole_at(Vec3(2.90, y, 2.05), Vec3::UnitZ()));
  for (double y : {-7.70, -3.03, 1.44, 5.95}) tags.push_back(linear_dipole_at(Vec3(-4.85, y, 1.85), Vec3::UnitZ()));
  return tags;
}

TEST(DoubleBounce, FastAgreesWithExhaustiveOnThePaperWarehouse) {
  const auto scene = std::make_shared<const Scene>(paper_warehouse_meshes(), MaterialAssignment{});
  TraceOptions ref = level_options(ChannelLevel::kDoubleBounce, CandidateMode::kExhaustive);
  ref.drop_below_db = 40.0;
  TraceOptions fast = ref;
  fast.candidates = CandidateMode::kExact;
  const RaytracedChannel exhaustive(scene, ref), quick(scene, fast);
  size_t doubles = 0;
  for (double y = -10.0; y <= 8.0; y += 3.0) {
    const Endpoint ant = linear_dipole_at(Vec3(-1.0, y, 1.68), Vec3::UnitZ());
    for (const Endpoint& tag : paper_tags()) {
      const auto a = exhaustive.paths(ant, tag, kF);
      const auto b = quick.paths(ant, tag, kF);
      ASSERT_EQ(a.size(), b.size()) << "antenna y " << y << " tag " << tag.pose.position.transpose();
      for (size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].kind, b[i].kind);
        EXPECT_NEAR(a[i].length_m, b[i].length_m, 1e-9);
        EXPECT_LT((a[i].point - b[i].point).norm(), 1e-6);
        EXPECT_LT((a[i].point2 - b[i].point2).norm(), 1e-6);
        EXPECT_LT(std::abs(a[i].contribution - b[i].contribution), 1e-12 * std::abs(a[i].contribution) + 1e-18);
        doubles += a[i].kind == PathKind::kReflection2;
      }
    }
  }
  EXPECT_GT(doubles, 100u);  // floor–rack, rack–rack and wall paths were really exercised
}

// one_way (links traced together: the plane pairs of each block of 16 nearby tags are found once and shared)
// against paths() per link (every ordered pair): the same channel, and far fewer pairs tried.
struct SharingResult {
  size_t links = 0, doubles = 0;
  double pairs_shared = 0.0, pairs_every = 0.0;  // try_plane_pair calls per link
};

SharingResult expect_shared_pairs_exact(const std::shared_ptr<const Scene>& scene, CandidateMode mode,
                                        const std::vector<Endpoint>& antennas, const std::vector<Endpoint>& tags,
                                        TraceOptions::Sharing sharing) {
  TraceOptions o = level_options(ChannelLevel::kDoubleBounce, mode);
  o.drop_below_db = 60.0;
  o.plane_pair_sharing = sharing;
  const RaytracedChannel channel(scene, o);
  SharingResult r;
  std::vector<std::complex<double>> h(tags.size());
  for (const Endpoint& ant : antennas) {
    tl_plane_pairs_tried = 0;
    channel.one_way(ant, tags, kF, h);
    r.pairs_shared += static_cast<double>(tl_plane_pairs_tried);
    tl_plane_pairs_tried = 0;
    for (size_t i = 0; i < tags.size(); ++i) {
      std::complex<double> sum{0.0, 0.0};
      for (const Path& p : channel.paths(ant, tags[i], kF)) {
        sum += p.contribution;
        r.doubles += p.kind == PathKind::kReflection2;
      }
      // The same paths in the same order: the same sum to rounding (1e-9 of |h| is the bound).
      EXPECT_LE(std::abs(h[i] - sum), 1e-9 * std::abs(sum) + 1e-300)
          << "antenna " << ant.pose.position.transpose() << " tag " << tags[i].pose.position.transpose();
    }
    r.pairs_every += static_cast<double>(tl_plane_pairs_tried);
    r.links += tags.size();
  }
  r.pairs_shared /= static_cast<double>(r.links);
  r.pairs_every /= static_cast<double>(r.links);
  return r;
}

TEST(DoubleBounceSharing, BlockPairsGiveEveryLinksPathsOnThePaperWarehouse) {
  const auto scene = std::make_shared<const Scene>(paper_warehouse_meshes(), MaterialAssignment{});
  std::vector<Endpoint> antennas, tags;
  for (double y = -10.0; y <= 8.0; y += 4.5) antennas.push_back(linear_dipole_at(Vec3(-1.0, y, 1.68), Vec3::UnitZ()));
  // The paper's tags and a grid along both rack faces at several heights (blocks of near and far tags).
  tags = paper_tags();
  for (double y = -9.0; y <= 7.0; y += 0.8)
    for (double z : {0.4, 1.1, 2.05})
      for (double x : {2.90, -4.85}) tags.push_back(linear_dipole_at(Vec3(x, y, z), Vec3::UnitZ()));
  const SharingResult r = expect_shared_pairs_exact(scene, CandidateMode::kExact, antennas, tags,
                                                    TraceOptions::Sharing::kAlways);
  EXPECT_GT(r.doubles, 500u);  // floor, rack and wall pairs really exercised
  // Shared, the links walked only their block's pairs.
  EXPECT_LT(r.pairs_shared, (2.0 / 3.0) * r.pairs_every) << r.pairs_shared << " of " << r.pairs_every;
  // Off, every link walks every ordered pair.
  const SharingResult off = expect_shared_pairs_exact(scene, CandidateMode::kExact, antennas, tags,
                                                      TraceOptions::Sharing::kNever);
  EXPECT_EQ(off.pairs_shared, off.pairs_every);
  // kAuto: these tags' first blocks keep more than 0.42 of the pairs (0.62 measured), where sharing costs more
  // than it saves (path_finder.cpp): the probe declines and every link walks every pair.
  const SharingResult probe = expect_shared_pairs_exact(scene, CandidateMode::kExact, antennas, tags,
                                                        TraceOptions::Sharing::kAuto);
  EXPECT_EQ(probe.pairs_shared, probe.pairs_every);
}

TEST(DoubleBounceSharing, ProbeSharesWhereABlockKeepsFewPairs) {
  // Tags in one bay of the paper warehouse's racks, the antenna in front of it: a block's windows meet few
  // planes, the probe keeps fewer than 0.42 of the pairs (0.27 measured) and shares, with the same paths.
  const auto scene = std::make_shared<const Scene>(paper_warehouse_meshes(), MaterialAssignment{});
  const std::vector<Endpoint> antennas{linear_dipole_at(Vec3(1.5, -3.0, 1.68), Vec3::UnitZ())};
  std::vector<Endpoint> tags;
  for (double y = -3.4; y <= -2.6; y += 0.1)
    for (double z : {1.0, 1.1, 1.2, 1.3, 1.4, 1.5, 1.6, 1.7})
      tags.push_back(linear_dipole_at(Vec3(2.90, y, z), Vec3::UnitZ()));
  const SharingResult r = expect_shared_pairs_exact(scene, CandidateMode::kExact, antennas, tags,
                                                    TraceOptions::Sharing::kAuto);
  EXPECT_LT(r.pairs_shared, 0.42 * r.pairs_every) << r.pairs_shared << " of " << r.pairs_every;
  EXPECT_GT(r.doubles, 20u);
}

TEST(DoubleBounceSharing, BlockPairsGiveEveryLinksPathsInRandomScenes) {
  // Random axis-aligned boxes (racks, crates; shared planes) and one tilted plate (a plane the windows cannot
  // bound: its pairs are always kept), tags anywhere including on and near the box faces, both candidate
  // modes.
  std::mt19937 rng(20261205);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int scene_index = 0; scene_index < 3; ++scene_index) {
    TriangleMesh m;
    m.name = "random";
    m.material_names = {"metal"};
    add_quad(m, Vec3(-6, -6, 0), Vec3(12, 0, 0), Vec3(0, 12, 0), 0, 1, 1);  // floor
    for (int b = 0; b < 8; ++b) {
      const Vec3 lo(-5 + 9 * u(rng), -5 + 9 * u(rng), std::round(4 * u(rng)) * 0.5);
      const Vec3 size(0.2 + 1.5 * u(rng), 0.2 + 1.5 * u(rng), 0.05 + 1.0 * u(rng));
      add_box(m, lo, lo + size, 0, 1, scene_index != 1);
    }
    add_quad(m, Vec3(4, -3, 0.5), Vec3(1.0, 0.6, 0), Vec3(0, 0, 1.5), 0, 1, 1);  // tilted about z
    const auto scene = std::make_shared<const Scene>(std::vector<TriangleMesh>{m}, MaterialAssignment{});
    std::vector<Endpoint> antennas, tags;
    for (int i = 0; i < 3; ++i)
      antennas.push_back(
          linear_dipole_at(Vec3(-5.5 + 11 * u(rng), -5.5 + 11 * u(rng), 0.3 + 2.5 * u(rng)), Vec3::UnitZ()));
    for (int i = 0; i < 120; ++i) {
      Vec3 p(-5.5 + 11 * u(rng), -5.5 + 11 * u(rng), 0.05 + 3.0 * u(rng));
      if (i % 4 == 0) p.z() = std::round(p.z() * 2.0) * 0.5 + (u(rng) < 0.5 ? 1e-3 : 2e-7);  // near a face
      tags.push_back(linear_dipole_at(p, Vec3(u(rng), u(rng), 1.0)));
    }
    for (CandidateMode mode : {CandidateMode::kExact, CandidateMode::kExhaustive}) {
      SCOPED_TRACE(::testing::Message() << "scene " << scene_index << " mode " << to_string(mode));
      const SharingResult r = expect_shared_pairs_exact(scene, mode, antennas, tags, TraceOptions::Sharing::kAlways);
      EXPECT_GT(r.doubles, 50u);
      EXPECT_LT(r.pairs_shared, r.pairs_every);
    }
  }
}

}  // namespace
}  // namespace rfidray
