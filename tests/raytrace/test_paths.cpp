// Paths and the ray-traced channel against closed forms: Friis, two-ray ground reflection (TE and TM,
// concrete and metal), a wall (blocked path, slab transmission), a metal plate behind the tag (image method),
// and the exact candidate search against the exhaustive reference on the paper warehouse.
#include <gtest/gtest.h>

#include <cmath>

#include "core/error.h"
#include "core/fresnel.h"
#include "core/units.h"
#include "raytrace/raytraced_channel.h"
#include "raytrace/warehouse.h"

namespace rfidray {
namespace {

using C = std::complex<double>;
constexpr double kF = 866e6;

Endpoint endpoint(const Vec3& p, const Vec3& pol_axis) {
  Endpoint e;
  e.pose.position = p;
  e.polarization.kind = PolarizationKind::kLinear;
  e.polarization.axis_local = pol_axis;
  return e;
}

std::shared_ptr<const Scene> scene_of(std::vector<TriangleMesh> meshes, MaterialAssignment a = {}) {
  return std::make_shared<const Scene>(std::move(meshes), a);
}

TriangleMesh plane_mesh(const std::string& name, const std::string& material, const Vec3& corner, const Vec3& u,
                        const Vec3& v, int n = 1) {
  TriangleMesh m;
  m.name = name;
  m.material_names = {material};
  add_quad(m, corner, u, v, 0, n, n);
  return m;
}

TraceOptions options(CandidateMode mode, ChannelLevel level = ChannelLevel::kSingleBounce) {
  TraceOptions o;
  o.candidates = mode;
  o.level = level;
  o.drop_below_db = 400.0;  // keep every path: the closed forms include them all
  return o;
}

C friis(double d) {
  const double lambda = wavelength_m(kF);
  return lambda / (4.0 * kPi * d) * std::polar(1.0, -wavenumber_rad_m(kF) * d);
}

double rel_err(C a, C b) { return std::abs(a - b) / std::abs(b); }

TEST(RaytracedChannel, FriisOnAnEmptyScene) {
  const auto scene = scene_of({});
  for (auto level : {ChannelLevel::kLos, ChannelLevel::kLosBlocked, ChannelLevel::kSingleBounce}) {
    const RaytracedChannel ch(scene, options(CandidateMode::kExact, level));
    for (double d : {0.3, 1.0, 4.2, 17.0}) {
      const Endpoint a = endpoint(Vec3(1, 2, 1.5), Vec3::UnitZ());
      const Endpoint t = endpoint(Vec3(1, 2, 1.5) + d * Vec3(0.6, 0.0, 0.8), Vec3::UnitY());
      const auto paths = ch.paths(a, t, kF);
      ASSERT_EQ(paths.size(), 1u);
      EXPECT_EQ(paths[0].kind, PathKind::kLineOfSight);
      EXPECT_NEAR(paths[0].length_m, d, 1e-12);
      // z projected transverse to (0.6, 0, 0.8) is (−0.8, 0, 0.6); against y: orthogonal → match 0.
      EXPECT_LT(std::abs(sum_paths(paths)), 1e-20);
      Endpoint t2 = t;
      t2.polarization.axis_local = Vec3::UnitZ();
      const auto p2 = ch.paths(a, t2, kF);
      ASSERT_EQ(p2.size(), 1u);
      EXPECT_LT(rel_err(sum_paths(p2), friis(d)), 1e-12);
      // Ideal channel (polarization taken as matched) agrees when polarizations match.
      EXPECT_LT(rel_err(sum_paths(p2), sum_paths(IdealChannel().paths(a, t2, kF))), 1e-12);
    }
  }
}

// Two-ray model over an infinite-enough ground plane z = 0:
//   h = λ/(4π) [e^{−jkd1}/d1 + Γ(θ) e^{−jkd2}/d2],  cos θ = (ha + ht)/d2.
// TE: both antennas linear, horizontal and perpendicular to the link's vertical plane (E ⊥ plane of incidence).
// TM: both vertical (E in the plane of incidence); the LoS match is 1 and the reflection's is Γ_TM in the
// p̂ = ŝ × k̂ basis of core/fresnel.h.
TEST(RaytracedChannel, TwoRayGroundReflectionMatchesClosedForm) {
  for (const std::string material : {"concrete", "metal"}) {
    // The plane is split into 20 × 20 quads so reflection points land inside, on edges and on vertices.
    const auto scene = scene_of({plane_mesh("ground", material, Vec3(-200, -200, 0), Vec3(400, 0, 0), Vec3(0, 400, 0), 20)});
    const RadioMaterial m = *builtin_material(material);
    for (auto mode : {CandidateMode::kExhaustive, CandidateMode::kExact}) {
      const RaytracedChannel ch(scene, options(mode));
      for (double phi : {0.0, 0.7, 2.0}) {
        const Vec3 along(std::cos(phi), std::sin(phi), 0.0), across(-std::sin(phi), std::cos(phi), 0.0);
        for (double ha : {0.5, 1.2, 3.0})
          for (double ht : {0.3, 1.2, 2.05})
            for (double d : {0.5, 2.0, 7.5, 30.0}) {
              const Vec3 pa = Vec3(0.25, -0.5, ha), pt = Vec3(0.25, -0.5, ht) + d * along;
              const double d1 = std::hypot(d, ha - ht), d2 = std::hypot(d, ha + ht);
              const FresnelCoefficients g = material_reflection(m, kF, (ha + ht) / d2);
              for (int te = 0; te < 2; ++te) {
                const Vec3 axis = te ? across : Vec3::UnitZ();
                const auto paths = ch.paths(endpoint(pa, axis), endpoint(pt, axis), kF);
                ASSERT_EQ(paths.size(), 2u) << material << " d=" << d;
                EXPECT_EQ(paths[0].kind, PathKind::kLineOfSight);
                EXPECT_EQ(paths[1].kind, PathKind::kReflection);
                EXPECT_EQ(paths[1].material, material);
                EXPECT_NEAR(paths[1].length_m, d2, 1e-12 * d2);
                // Reflection point: where the line to the image crosses z = 0.
                const Vec3 p_expected = pa + (ha / (ha + ht)) * (Vec3(pt.x(), pt.y(), -ht) - pa);
                EXPECT_LT((paths[1].point - p_expected).norm(), 1e-12);
                const C gamma = te ? g.te : g.tm;
                const C expected = wavelength_m(kF) / (4.0 * kPi) *
                                   (std::polar(1.0, -wavenumber_rad_m(kF) * d1) / d1 +
                                    gamma * std::polar(1.0, -wavenumber_rad_m(kF) * d2) / d2);
                EXPECT_LT(rel_err(sum_paths(paths), expected), 1e-9)
                    << material << (te ? " TE" : " TM") << " ha=" << ha << " ht=" << ht << " d=" << d;
              }
            }
      }
    }
  }
}

TEST(RaytracedChannel, WallGivesBlockedPathWithSlabLoss) {
  // One concrete sheet at x = 2 (normal x); the slab thickness comes from the material assignment.
  MaterialAssignment a;
  a.thickness_m = 0.2;
  const auto wall = plane_mesh("wall", "concrete", Vec3(2, -5, -5), Vec3(0, 10, 0), Vec3(0, 0, 10));
  const auto scene = scene_of({wall}, a);
  const RadioMaterial concrete = scene->materials()[0];
  ASSERT_DOUBLE_EQ(concrete.thickness_m, 0.2);
  const Endpoint ant = endpoint(Vec3(0, 0, 1), Vec3::UnitZ());
  // Oblique in the xy plane: z-polarization is ⊥ the plane of incidence → pure TE.
  const Vec3 tag_pos(4.0, 1.5, 1.0);
  const Endpoint tag = endpoint(tag_pos, Vec3::UnitZ());
  const double d = tag_pos.norm() > 0 ? (tag_pos - ant.pose.position).norm() : 0.0;
  const double cos_theta = 4.0 / d;
  const C tau = material_transmission(concrete, kF, cos_theta).te;
  ASSERT_GT(std::abs(tau), 0.05);
  ASSERT_LT(std::abs(tau), 0.95);

  const RaytracedChannel blocked(scene, options(CandidateMode::kExact, ChannelLevel::kLosBlocked));
  auto paths = blocked.paths(ant, tag, kF);
  ASSERT_EQ(paths.size(), 1u);
  EXPECT_EQ(paths[0].kind, PathKind::kBlocked);
  EXPECT_EQ(paths[0].crossings, 1);
  EXPECT_EQ(paths[0].material, "concrete");
  EXPECT_LT((paths[0].point - Vec3(2.0, 0.75, 1.0)).norm(), 1e-5);  // first crossing (Embree float)
  EXPECT_LT(rel_err(sum_paths(paths), tau * friis(d)), 1e-12);
  // Transmission through the wall at normal incidence: |T|² in dB, for the docs of the blocked model.
  const C tau0 = material_transmission(concrete, kF, 1.0).te;
  auto p0 = blocked.paths(ant, endpoint(Vec3(4, 0, 1), Vec3::UnitZ()), kF);
  ASSERT_EQ(p0.size(), 1u);
  EXPECT_LT(rel_err(sum_paths(p0), tau0 * friis(4.0)), 1e-12);

  // `los` drops the obstructed direct path; a metal wall is opaque at every level.
  const RaytracedChannel los(scene, options(CandidateMode::kExact, ChannelLevel::kLos));
  EXPECT_TRUE(los.paths(ant, tag, kF).empty());
  MaterialAssignment metal;
  metal.override_all = "metal";
  const RaytracedChannel opaque(scene_of({wall}, metal), options(CandidateMode::kExact, ChannelLevel::kSingleBounce));
  EXPECT_TRUE(opaque.paths(ant, tag, kF).empty());
  // Two sheets: two crossings, coefficients multiply.
  const auto second = plane_mesh("wall2", "concrete", Vec3(3, -5, -5), Vec3(0, 10, 0), Vec3(0, 0, 10));
  const RaytracedChannel two(scene_of({wall, second}, a), options(CandidateMode::kExact, ChannelLevel::kLosBlocked));
  paths = two.paths(ant, tag, kF);
  ASSERT_EQ(paths.size(), 1u);
  EXPECT_EQ(paths[0].crossings, 2);
  EXPECT_LT(rel_err(sum_paths(paths), tau * tau * friis(d)), 1e-12);
}

// A wall as a closed box of a solid material: the entry and exit crossings are one P.2040 slab of the wall's
// thickness (chord · cos θ along the entry face's normal), the same as the one-sheet wall of that thickness; a
// tag inside the wall gets the slab up to it; two walls multiply. Without `solid` the two faces would each be a
// slab (the test's first check fails then).
TEST(RaytracedChannel, SolidWallIsOneSlabOfItsThickness) {
  const double t = 0.2;
  TriangleMesh box;
  box.name = "wall";
  box.material_names = {"concrete"};
  add_box(box, Vec3(2.0, -5.0, -5.0), Vec3(2.0 + t, 5.0, 5.0), 0);  // faces at x = 2 and 2.2
  MaterialAssignment solid;
  solid.thickness_m = t;  // its faces' reflection: the slab of the wall's thickness
  solid.solid = true;
  const auto scene = scene_of({box}, solid);
  ASSERT_TRUE(scene->materials()[0].solid);
  const RadioMaterial concrete = scene->materials()[0];
  const RaytracedChannel blocked(scene, options(CandidateMode::kExact, ChannelLevel::kLosBlocked));
  const Endpoint ant = endpoint(Vec3(0, 0, 1), Vec3::UnitZ());
  for (const Vec3& tag_pos : {Vec3(4.0, 0.0, 1.0), Vec3(4.0, 1.5, 1.0), Vec3(4.0, 3.0, 1.0)}) {
    const double d = (tag_pos - ant.pose.position).norm();
    const double cos_theta = 4.0 / d;  // TE: z-polarization ⊥ the plane of incidence (xy)
    const C tau = material_transmission(concrete, kF, cos_theta).te;
    const auto paths = blocked.paths(ant, endpoint(tag_pos, Vec3::UnitZ()), kF);
    ASSERT_EQ(paths.size(), 1u);
    EXPECT_EQ(paths[0].crossings, 1);  // entry and exit: one slab
    // The scene keeps its vertices in float: the back face at 2.2 is 4.8e-8 m off, and the slab's phase turns
    // ~42 rad per metre of concrete (k·√ε'): ~2e-6 of the field.
    EXPECT_LT(rel_err(sum_paths(paths), tau * friis(d)), 1e-5) << tag_pos.transpose();
  }
  // A tag inside the wall, 5 cm in: the slab of 5 cm.
  {
    RadioMaterial slab5 = concrete;
    slab5.thickness_m = 0.05;
    const Vec3 tag_pos(2.05, 0.0, 1.0);
    const auto paths = blocked.paths(ant, endpoint(tag_pos, Vec3::UnitZ()), kF);
    ASSERT_EQ(paths.size(), 1u);
    EXPECT_LT(rel_err(sum_paths(paths), material_transmission(slab5, kF, 1.0).te * friis(2.05)), 1e-12);
  }
  // In by the front face, out by the end face y = 5 (a corner cut): no slab, no path.
  EXPECT_TRUE(blocked.paths(endpoint(Vec3(0, 3.95, 1), Vec3::UnitZ()), endpoint(Vec3(2.3, 5.1, 1), Vec3::UnitZ()), kF)
                  .empty());
  // A plasterboard sheet inside the wall (x = 2.1) is crossed as a sheet; the wall stays one slab around it.
  {
    TriangleMesh inner;
    inner.name = "inner";
    inner.material_names = {"plasterboard"};
    add_quad(inner, Vec3(2.1, -5, -5), Vec3(0, 10, 0), Vec3(0, 0, 10), 0, 1, 1);
    MaterialAssignment mixed;
    mixed.user_materials = {concrete};  // solid, 0.2 m
    RadioMaterial board = *builtin_material("plasterboard");
    board.thickness_m = 0.0125;
    mixed.user_materials.push_back(board);
    const RaytracedChannel ch(scene_of({box, inner}, mixed), options(CandidateMode::kExact, ChannelLevel::kLosBlocked));
    const auto paths = ch.paths(ant, endpoint(Vec3(4, 0, 1), Vec3::UnitZ()), kF);
    ASSERT_EQ(paths.size(), 1u);
    const C expected = material_transmission(concrete, kF, 1.0).te * material_transmission(board, kF, 1.0).te;
    EXPECT_LT(rel_err(sum_paths(paths), expected * friis(4.0)), 1e-5);  // float vertices, as above
  }
  // Two solid walls: two slabs.
  TriangleMesh box2 = box;
  box2.name = "wall2";
  for (Vec3& v : box2.vertices) v.x() += 1.0;
  const RaytracedChannel two(scene_of({box, box2}, solid), options(CandidateMode::kExact, ChannelLevel::kLosBlocked));
  const C tau0 = material_transmission(concrete, kF, 1.0).te;
  const auto paths = two.paths(ant, endpoint(Vec3(4, 0, 1), Vec3::UnitZ()), kF);
  ASSERT_EQ(paths.size(), 1u);
  EXPECT_EQ(paths[0].crossings, 2);
  EXPECT_LT(rel_err(sum_paths(paths), tau0 * tau0 * friis(4.0)), 1e-5);  // float vertices, as above
}

TEST(RaytracedChannel, MetalPlateBehindTheTagReflectsAtTheImagePoint) {
  // Plate x = 3, y −1…1, z 0…2; tag at x = 2.5 in front of it; antenna at the origin side.
  const auto plate = plane_mesh("plate", "metal", Vec3(3, -1, 0), Vec3(0, 2, 0), Vec3(0, 0, 2));
  const auto scene = scene_of({plate});
  for (auto mode : {CandidateMode::kExhaustive, CandidateMode::kExact}) {
    const RaytracedChannel ch(scene, options(mode));
    // Same height, offset in y: image (3.5, 0.5, 1); P on x = 3 at y = −0.5 + (3/3.5)·1.
    const Endpoint ant = endpoint(Vec3(0, -0.5, 1), Vec3::UnitZ());
    const Endpoint tag = endpoint(Vec3(2.5, 0.5, 1), Vec3::UnitZ());
    const auto paths = ch.paths(ant, tag, kF);
    ASSERT_EQ(paths.size(), 2u);
    const Path& r = paths[1];
    EXPECT_EQ(r.kind, PathKind::kReflection);
    EXPECT_EQ(r.material, "metal");
    EXPECT_NEAR(r.length_m, std::sqrt(3.5 * 3.5 + 1.0), 1e-12);
    EXPECT_LT((r.point - Vec3(3.0, -0.5 + 3.0 / 3.5, 1.0)).norm(), 1e-12);
    // z is ⊥ the (horizontal) plane of incidence → TE, Γ = −1 on metal: the tag sees −1.
    EXPECT_LT(std::abs(r.coefficient - C(-1.0, 0.0)), 1e-12);
    EXPECT_LT(rel_err(r.contribution, -friis(r.length_m)), 1e-12);
    // A tag whose image point falls off the plate gets no reflection.
    const auto off = ch.paths(ant, endpoint(Vec3(2.5, 2.5, 1), Vec3::UnitZ()), kF);
    ASSERT_EQ(off.size(), 1u);
    EXPECT_EQ(off[0].kind, PathKind::kLineOfSight);
    // An antenna behind the plate: no reflection, and the direct path through metal is gone.
    EXPECT_TRUE(ch.paths(endpoint(Vec3(4, 0, 1), Vec3::UnitZ()), tag, kF).empty());
  }
}

TEST(RaytracedChannel, OccludedLegsRemoveTheReflection) {
  // Ground plus a metal screen standing between antenna and the ground reflection point, above the LoS.
  const auto ground = plane_mesh("ground", "concrete", Vec3(-10, -10, 0), Vec3(20, 0, 0), Vec3(0, 20, 0));
  // Screen at x = 1, z 0…0.6: leg 1 of the ground reflection (P = (2, 0, 0)) crosses it at z = 0.5,
  // the LoS at z = 1 passes above. Mirrored at x = 3 it blocks leg 2 instead.
  const auto screen = plane_mesh("screen", "metal", Vec3(1, -1, 0.0), Vec3(0, 2, 0), Vec3(0, 0, 0.6));
  const auto screen2 = plane_mesh("screen2", "metal", Vec3(3, -1, 0.0), Vec3(0, 2, 0), Vec3(0, 0, 0.6));
  for (auto mode : {CandidateMode::kExhaustive, CandidateMode::kExact}) {
    const Endpoint a = endpoint(Vec3(0, 0, 1), Vec3::UnitZ()), t = endpoint(Vec3(4, 0, 1), Vec3::UnitZ());
    const auto open = RaytracedChannel(scene_of({ground}), options(mode)).paths(a, t, kF);
    ASSERT_EQ(open.size(), 2u);  // without the screen the ground reflection is there
    EXPECT_EQ(open[1].material, "concrete");
    for (const auto& s : {screen, screen2}) {
      const auto paths = RaytracedChannel(scene_of({ground, s}), options(mode)).paths(a, t, kF);
      ASSERT_FALSE(paths.empty());
      EXPECT_EQ(paths[0].kind, PathKind::kLineOfSight);
      for (const Path& p : paths) EXPECT_NE(p.material, "concrete") << "ground reflection should be occluded";
    }
  }
}

TEST(RaytracedChannel, DropThresholdIsRelativeToTheStrongestPath) {
  const auto scene = scene_of({plane_mesh("ground", "concrete", Vec3(-50, -50, 0), Vec3(100, 0, 0), Vec3(0, 100, 0))});
  const Endpoint a = endpoint(Vec3(0, 0, 1), Vec3::UnitZ()), t = endpoint(Vec3(5, 0, 1), Vec3::UnitZ());
  TraceOptions o = options(CandidateMode::kExact);
  const auto all = RaytracedChannel(scene, o).paths(a, t, kF);
  ASSERT_EQ(all.size(), 2u);
  const double ratio_db = 20.0 * std::log10(std::abs(all[0].contribution) / std::abs(all[1].contribution));
  o.drop_below_db = ratio_db + 0.1;
  EXPECT_EQ(RaytracedChannel(scene, o).paths(a, t, kF).size(), 2u);
  o.drop_below_db = ratio_db - 0.1;
  EXPECT_EQ(RaytracedChannel(scene, o).paths(a, t, kF).size(), 1u);
}

// The ten tags of scenes/paper_warehouse.yaml.
std::vector<Endpoint> paper_tags() {
  std::vector<Endpoint> tags;
  for (double y : {0.57, -1.24, -3.03, -4.82, -6.75, -8.66}) tags.push_back(endpoint(Vec3(2.90, y, 2.05), Vec3::UnitZ()));
  for (double y : {-7.70, -3.03, 1.44, 5.95}) tags.push_back(endpoint(Vec3(-4.85, y, 1.85), Vec3::UnitZ()));
  return tags;
}

TEST(RaytracedChannel, ExactCandidatesAgreeWithExhaustiveOnThePaperWarehouse) {
  const auto scene = scene_of(paper_warehouse_meshes());
  TraceOptions ref = options(CandidateMode::kExhaustive);
  ref.drop_below_db = 40.0;
  TraceOptions fast = ref;
  fast.candidates = CandidateMode::kExact;
  const RaytracedChannel exhaustive(scene, ref), quick(scene, fast);
  const auto tags = paper_tags();
  size_t reflections = 0, blocked = 0;
  // The mobile antenna along the robot path (x = −1, then y = 8), at two heights, plus the fixed antenna.
  std::vector<Vec3> antennas;
  for (double y = -10.0; y <= 8.0; y += 0.75) antennas.emplace_back(-1.0, y, y < 0 ? 0.6 : 1.68);
  for (double x = -0.5; x <= 3.0; x += 0.5) antennas.emplace_back(x, 8.0, 1.68);
  antennas.emplace_back(3.5, -4.0, 2.0);
  for (const Vec3& pos : antennas) {
    for (int pol = 0; pol < 3; ++pol) {
      Endpoint ant = endpoint(pos, pol == 0 ? Vec3::UnitZ() : Vec3::UnitY());
      if (pol == 2) ant.polarization.kind = PolarizationKind::kCircularRight;
      for (const Endpoint& tag : tags) {
        const auto a = exhaustive.paths(ant, tag, kF);
        const auto b = quick.paths(ant, tag, kF);
        ASSERT_EQ(a.size(), b.size()) << "antenna " << pos.transpose() << " tag " << tag.pose.position.transpose();
        for (size_t i = 0; i < a.size(); ++i) {
          EXPECT_EQ(a[i].kind, b[i].kind);
          EXPECT_EQ(a[i].material, b[i].material);
          EXPECT_NEAR(a[i].length_m, b[i].length_m, 1e-9);
          EXPECT_LT((a[i].point - b[i].point).norm(), 1e-6);
          EXPECT_LT(std::abs(a[i].contribution - b[i].contribution), 1e-12 * std::abs(a[i].contribution) + 1e-18);
          reflections += a[i].kind == PathKind::kReflection;
          blocked += a[i].kind == PathKind::kBlocked;
        }
      }
    }
  }
  // The comparison exercised real multipath: floor, walls and rack reflections.
  EXPECT_GT(reflections, 500u);
}

TEST(RaytracedChannel, BatchEqualsPerLinkAndIsThreadSafe) {
  const auto scene = scene_of(paper_warehouse_meshes());
  for (int rays : {0, 2048}) {
    TraceOptions o;
    o.candidate_rays = rays;
    const RaytracedChannel ch(scene, o);
    std::vector<Endpoint> tags;
    for (int i = 0; i < 300; ++i)
      tags.push_back(endpoint(Vec3(i % 2 ? 2.90 : -4.85, -9.0 + 0.03 * i, i % 2 ? 2.05 : 1.85), Vec3::UnitZ()));
    const Endpoint ant = endpoint(Vec3(-1.0, -2.0, 0.6), Vec3::UnitZ());
    std::vector<C> h(tags.size());
    ch.one_way(ant, tags, kF, h);  // OpenMP over tags (≥ 64)
    size_t nonzero = 0;
    for (size_t i = 0; i < tags.size(); ++i) {
      EXPECT_EQ(h[i], sum_paths(ch.paths(ant, tags[i], kF))) << i;
      nonzero += std::abs(h[i]) > 0.0;
    }
    EXPECT_GT(nonzero, 250u);
  }
}

TEST(RaytracedChannel, RejectsBadLinks) {
  const RaytracedChannel ch(scene_of(paper_warehouse_meshes()));
  const Endpoint a = endpoint(Vec3(0, 0, 1), Vec3::UnitZ());
  EXPECT_THROW(ch.paths(a, a, kF), InputError);
  EXPECT_THROW(ch.paths(a, endpoint(Vec3(NAN, 0, 1), Vec3::UnitZ()), kF), InputError);
  EXPECT_THROW(ch.paths(a, endpoint(Vec3(1, 0, 1), Vec3::UnitZ()), -1.0), InputError);
  std::vector<Endpoint> tags = {endpoint(Vec3(1, 0, 1), Vec3::UnitZ()), a};
  std::vector<C> h(2);
  EXPECT_THROW(ch.one_way(a, tags, kF, h), InputError);
  EXPECT_EQ(ch.name(), "single-bounce");
  EXPECT_THROW(parse_channel_level("multi-bounce", "channel"), InputError);
}

}  // namespace
}  // namespace rfidray

namespace rfidray {
namespace {

TEST(PathFinder, MaxPathLengthCullsLongerPaths) {
  // scenes/ground_wall: LoS 3.0414 m, ground reflection 3.9051 m, wall reflection 7.0178 m.
  const auto scene = scene_of(ground_and_wall_meshes());
  const Endpoint a = endpoint(Vec3(0, 0, 1), Vec3::UnitZ()), t = endpoint(Vec3(3, 0, 1.5), Vec3::UnitZ());
  auto lengths = [&](double max_m) {
    TraceOptions o;
    o.max_path_length_m = max_m;
    o.drop_below_db = 300;
    std::vector<double> out;
    for (const Path& p : RaytracedChannel(scene, o).paths(a, t, kF)) out.push_back(p.length_m);
    return out;
  };
  EXPECT_EQ(lengths(1e9).size(), 3u);
  const auto five = lengths(5.0);
  ASSERT_EQ(five.size(), 2u);
  EXPECT_NEAR(five[1], std::sqrt(9.0 + 2.5 * 2.5), 1e-9);
  EXPECT_TRUE(lengths(3.0).empty());  // even the direct path is longer: no path, h = 0
  TraceOptions bad;
  bad.max_path_length_m = 0.0;
  EXPECT_THROW(RaytracedChannel(scene, bad), InputError);
}

// Per-pose candidate rays (PoseCandidates): the cells of each plane the antenna's rays see. Enough rays find
// the exhaustive search's paths; few rays miss some (the mask really culls).
TEST(PathFinder, CandidateRaysConvergeToTheExhaustiveSearch) {
  const auto scene = scene_of(paper_warehouse_meshes());
  TraceOptions ref_o;
  ref_o.candidates = CandidateMode::kExhaustive;
  ref_o.drop_below_db = 300;
  const RaytracedChannel reference(scene, ref_o);
  auto found_fraction = [&](int rays) {
    TraceOptions o = ref_o;
    o.candidates = CandidateMode::kExact;
    o.candidate_rays = rays;
    const RaytracedChannel fast(scene, o);
    double total = 0.0, found = 0.0;
    for (int k = 0; k < 8; ++k) {
      const Endpoint ant = endpoint(Vec3(-1.0, -9.0 + 2.2 * k, 1.68), Vec3::UnitZ());
      for (int i = 0; i < 10; ++i) {
        const Endpoint tag = endpoint(Vec3(i % 2 ? 2.90 : -4.85, -8.0 + 1.5 * i, i % 2 ? 2.05 : 1.85), Vec3::UnitZ());
        const auto ref = reference.paths(ant, tag, kF);
        const auto got = fast.paths(ant, tag, kF);
        for (const Path& p : ref) total += std::norm(p.contribution);
        for (const Path& p : got) {
          // Every path the fast search reports is one of the reference's.
          bool match = false;
          for (const Path& q : ref) match = match || ((q.point - p.point).norm() < 1e-6 && q.kind == p.kind);
          EXPECT_TRUE(match) << "spurious path at " << p.point.transpose();
          found += std::norm(p.contribution);
        }
      }
    }
    return found / total;
  };
  const double many = found_fraction(1 << 13), few = found_fraction(64);
  EXPECT_GT(many, 0.999);
  EXPECT_LT(few, many - 0.01);
}

}  // namespace
}  // namespace rfidray

namespace rfidray {
namespace {

// A tessellated ground with ±0.5 mm vertex noise, merged into one facet with a 5 mm tolerance: the reflection
// legs must keep clear of the facet's real surface (up to its flatness off the fitted plane), or the ray to
// the reflection point stops short of the surface and the ground reflection is lost.
TEST(PathFinder, NoisyMergedFacetStillReflects) {
  TriangleMesh ground = plane_mesh("ground", "concrete", Vec3(-2, -2, 0), Vec3(4, 0, 0), Vec3(0, 4, 0), 4);
  uint64_t state = 7;
  for (Vec3& v : ground.vertices) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    v.z() += 0.5e-3 * (double(state >> 11) / double(1ULL << 53) * 2.0 - 1.0);
  }
  SceneOptions so;
  so.facets.distance_tolerance_m = 5e-3;
  so.facets.angle_tolerance_rad = 5e-3;
  const auto scene = std::make_shared<const Scene>(std::vector<TriangleMesh>{ground}, MaterialAssignment{}, so);
  ASSERT_EQ(scene->facets().size(), 1u);
  EXPECT_GT(scene->facets()[0].flatness_m, 1e-4);
  for (CandidateMode mode : {CandidateMode::kExact, CandidateMode::kExhaustive}) {
    TraceOptions o;
    o.candidates = mode;
    int found = 0;
    for (int k = 0; k < 20; ++k) {
      const Endpoint a = endpoint(Vec3(-1.5 + 0.05 * k, -1.0, 1.0), Vec3::UnitZ());
      const Endpoint t = endpoint(Vec3(1.5, 0.5 + 0.05 * k, 1.5), Vec3::UnitZ());
      for (const Path& p : RaytracedChannel(scene, o).paths(a, t, kF)) found += p.kind == PathKind::kReflection;
    }
    EXPECT_EQ(found, 20) << to_string(mode);
  }
}

}  // namespace
}  // namespace rfidray
