// Level full (raytrace/diffraction.cpp, raytrace/edges.h): edges extracted from merged facets, and a knife edge
// (a perfectly conducting half-plane) lit by a distant source against Sommerfeld's exact half-plane solution.
#include <gtest/gtest.h>

#include <cmath>

#include "core/units.h"
#include "core/utd.h"
#include "raytrace/raytraced_channel.h"
#include "raytrace/warehouse.h"

namespace rfidray {
namespace {

using C = std::complex<double>;
constexpr double kF = 866e6;

Endpoint linear(const Vec3& p, const Vec3& axis) {
  Endpoint e;
  e.pose.position = p;
  e.polarization.kind = PolarizationKind::kLinear;
  e.polarization.axis_local = axis.normalized();
  return e;
}

TEST(Edges, BoxSheetAndJunction) {
  // A closed metal box: 12 right-angled wedges (α = 90° or 270° depending on the winding), no free edge.
  TriangleMesh box;
  box.name = "box";
  box.material_names = {"metal"};
  add_box(box, Vec3(0, 0, 0), Vec3(1, 2, 3), 0, 2, true);  // tessellated: edges are merged back to 12
  const Scene boxes({box}, MaterialAssignment{});
  const auto edges = extract_edges(boxes);
  ASSERT_EQ(edges.size(), 12u);
  for (const Edge& e : edges) {
    EXPECT_FALSE(e.half_plane());
    EXPECT_NEAR(std::min(e.alpha_rad, kTwoPi - e.alpha_rad), kPi / 2.0, 1e-9);
    EXPECT_TRUE(std::abs(e.length_m - 1.0) < 1e-9 || std::abs(e.length_m - 2.0) < 1e-9 ||
                std::abs(e.length_m - 3.0) < 1e-9);
  }
  // A sheet: four free edges (half-planes). Standing on a floor: its bottom edge is a junction, not an edge;
  // the floor's own outline gives four more.
  TriangleMesh sheet;
  sheet.name = "sheet";
  sheet.material_names = {"metal"};
  add_quad(sheet, Vec3(0, 0, 0), Vec3(2, 0, 0), Vec3(0, 0, 1), 0, 3, 3);
  EXPECT_EQ(extract_edges(Scene({sheet}, MaterialAssignment{})).size(), 4u);
  TriangleMesh floor;
  floor.name = "floor";
  floor.material_names = {"concrete"};
  add_quad(floor, Vec3(-5, -5, 0), Vec3(10, 0, 0), Vec3(0, 10, 0), 0, 1, 1);
  const auto both = extract_edges(Scene({sheet, floor}, MaterialAssignment{}));
  EXPECT_EQ(both.size(), 3u + 4u);
  for (const Edge& e : both) EXPECT_TRUE(e.half_plane());
  // No edge inside a flat tessellated facet: a 3 × 3 tessellated square still has only its 4 outline edges.
}

// Sommerfeld's exact total field for a plane wave e^{jkρ cos(φ − φ')} on a perfectly conducting half-plane,
// E ∥ edge (soft, Dirichlet): u = V(φ − φ') − V(φ + φ'),
// V(ξ) = e^{jkρ cos ξ} e^{jπ/4}/√π ∫_{−∞}^{√(2kρ) cos(ξ/2)} e^{−jτ²} dτ (Born & Wolf §11.5).
C sommerfeld_soft(double k, double rho, double phi, double phi_prime) {
  auto v = [&](double xi) {
    return std::polar(1.0, k * rho * std::cos(xi)) * std::polar(1.0, kPi / 4.0) / std::sqrt(kPi) *
           fresnel_from_minus_infinity(std::sqrt(2.0 * k * rho) * std::cos(xi / 2.0));
  };
  return v(phi - phi_prime) - v(phi + phi_prime);
}

// The knife edge: the metal half-plane y = 0, x ≥ 0 (a 3 km sheet; its far edges add < 1e-3 of the field),
// edge along z through the origin. The source is 100 km away at angle φ' = 60°, E ∥ edge (z); the tag moves
// on the circle ρ = 5 m (kρ ≈ 91) round the edge. h normalized by the incident field at the edge is the
// plane-wave total field up to (kρ²/2R, ρ/R) ≈ (2e-3 rad, 5e-5).
TEST(Diffraction, KnifeEdgeMatchesSommerfeldHalfPlane) {
  TriangleMesh sheet;
  sheet.name = "knife";
  sheet.material_names = {"metal"};
  add_quad(sheet, Vec3(0, 0, -1500), Vec3(3000, 0, 0), Vec3(0, 0, 3000), 0, 1, 1);
  const auto scene = std::make_shared<const Scene>(std::vector<TriangleMesh>{sheet}, MaterialAssignment{});
  TraceOptions o;
  o.level = ChannelLevel::kFull;
  o.drop_below_db = 400.0;
  // Embree traces in float: 100 km away a ray's origin is good to ~8 mm, so the reflection legs keep 5 cm
  // clear of the sheet (the default 0.1 mm suits scenes of tens of metres).
  o.surface_epsilon_m = 0.05;
  const RaytracedChannel full(scene, o);
  o.level = ChannelLevel::kDoubleBounce;
  const RaytracedChannel no_diffraction(scene, o);
  const double k = wavenumber_rad_m(kF), rho = 5.0, range = 1e5;
  const double phi_prime = 60.0 * kPi / 180.0;  // reflection boundary φ = 120°, incident boundary φ = 240°
  const Endpoint source = linear(range * Vec3(std::cos(phi_prime), std::sin(phi_prime), 0.0), Vec3::UnitZ());
  const C incident_at_edge = path_contribution(range, 1.0, kF);
  auto field = [&](const RaytracedChannel& ch, double phi_deg) {
    const double phi = phi_deg * kPi / 180.0;
    return sum_paths(ch.paths(source, linear(rho * Vec3(std::cos(phi), std::sin(phi), 0.0), Vec3::UnitZ()), kF)) /
           incident_at_edge;
  };
  // Lit (with and without the reflection), both transition regions (±1…±6° about 120° and 240°), the shadow.
  std::vector<double> angles;
  for (double a = 2.5; a < 358.0; a += 5.0) angles.push_back(a);
  for (double b : {120.0, 240.0})
    for (double off : {-6.0, -3.0, -2.0, -1.0, 1.0, 2.0, 3.0, 6.0}) angles.push_back(b + off);
  int compared = 0, shadow = 0;
  for (double phi_deg : angles) {
    const C exact = sommerfeld_soft(k, rho, phi_deg * kPi / 180.0, phi_prime);
    const C traced = field(full, phi_deg);
    // Everywhere: close in the complex plane (also in the nulls of the lit region's two-wave interference).
    EXPECT_LT(std::abs(traced - exact), 0.01) << "φ = " << phi_deg << "°";
    if (std::abs(exact) < 0.1) continue;  // −20 dB nulls: a ratio means nothing there
    ++compared;
    shadow += phi_deg > 240.0;
    EXPECT_LT(std::abs(20.0 * std::log10(std::abs(traced) / std::abs(exact))), 0.5) << "φ = " << phi_deg << "°";
    EXPECT_LT(std::abs(std::arg(traced / exact)), 0.05) << "φ = " << phi_deg << "°";
  }
  EXPECT_GT(compared, 60);
  EXPECT_GT(shadow, 5);
  // Continuity across the shadow boundaries: over ±0.5° |h| changes as the exact field does (which varies
  // quickly there: the two-wave interference near the reflection boundary), where the level without
  // diffraction jumps by about half the incident field.
  for (double b : {120.0, 240.0}) {
    auto change = [&](auto&& f) { return std::abs(f(b + 0.5)) - std::abs(f(b - 0.5)); };
    const double exact = change([&](double deg) { return sommerfeld_soft(k, rho, deg * kPi / 180.0, phi_prime); });
    EXPECT_LT(std::abs(change([&](double deg) { return field(full, deg); }) - exact), 0.02) << "boundary " << b;
    EXPECT_GT(std::abs(change([&](double deg) { return field(no_diffraction, deg); }) - exact), 0.3) << "boundary " << b;
  }
  // Deep in the shadow the tag is reached by diffraction alone.
  const auto deep = full.paths(source, linear(rho * Vec3(std::cos(5.0), std::sin(5.0), 0.0), Vec3::UnitZ()), kF);
  ASSERT_FALSE(deep.empty());
  for (const Path& p : deep) EXPECT_EQ(p.kind, PathKind::kDiffraction);
  EXPECT_LT(deep.front().point.norm(), 1e-9);  // on the edge, at the Fermat point z = 0
  EXPECT_TRUE(no_diffraction.paths(source, linear(rho * Vec3(std::cos(5.0), std::sin(5.0), 0.0), Vec3::UnitZ()), kF).empty());
}

// Off the plane perpendicular to the edge the diffraction point moves along the edge (Fermat: equal angles
// with the edge on both sides, Keller's cone), and a tag hidden behind a metal rack is reached.
TEST(Diffraction, FermatPointAndAHiddenTagInThePaperWarehouse) {
  TriangleMesh sheet;
  sheet.name = "knife";
  sheet.material_names = {"metal"};
  add_quad(sheet, Vec3(0, 0, -50), Vec3(50, 0, 0), Vec3(0, 0, 100), 0, 1, 1);
  const auto scene = std::make_shared<const Scene>(std::vector<TriangleMesh>{sheet}, MaterialAssignment{});
  TraceOptions o;
  o.level = ChannelLevel::kFull;
  o.drop_below_db = 400.0;
  const RaytracedChannel full(scene, o);
  const Endpoint a = linear(Vec3(3.0, 2.0, 1.0), Vec3::UnitZ()), t = linear(Vec3(2.0, -1.5, 4.0), Vec3::UnitZ());
  const auto paths = full.paths(a, t, kF);
  const Path* d = nullptr;
  for (const Path& p : paths)
    if (p.kind == PathKind::kDiffraction && std::abs(p.point.x()) < 1e-9 && std::abs(p.point.y()) < 1e-9) d = &p;
  ASSERT_NE(d, nullptr);
  const Vec3 in = (d->point - a.pose.position).normalized(), out = (t.pose.position - d->point).normalized();
  EXPECT_NEAR(in.z(), out.z(), 1e-12);  // equal angles with the edge
  EXPECT_NEAR(d->length_m, (d->point - a.pose.position).norm() + (t.pose.position - d->point).norm(), 1e-12);
  // Fermat's length: unfolded, √(Δz² + (ρa + ρt)²).
  EXPECT_NEAR(d->length_m, std::hypot(3.0, std::hypot(3.0, 2.0) + std::hypot(2.0, 1.5)), 1e-12);

  // Paper warehouse: a tag on the back of the east rack row (x = 3.85 + 0.05), the antenna in the aisle.
  const auto warehouse = std::make_shared<const Scene>(paper_warehouse_meshes(), MaterialAssignment{});
  TraceOptions w;
  w.level = ChannelLevel::kSingleBounce;
  const RaytracedChannel sb(warehouse, w);
  w.level = ChannelLevel::kFull;
  const RaytracedChannel fl(warehouse, w);
  const Endpoint ant = linear(Vec3(-1.0, -2.3, 1.68), Vec3::UnitZ());
  const Endpoint hidden = linear(Vec3(3.0, -2.3, 1.5), Vec3::UnitZ());  // inside the rack, between shelves
  const auto with = fl.paths(ant, hidden, kF);
  size_t diffracted = 0;
  for (const Path& p : with) diffracted += p.kind == PathKind::kDiffraction;
  EXPECT_GT(diffracted, 0u);
  EXPECT_GT(std::abs(sum_paths(with)), 0.0);
  (void)sb;
}

}  // namespace
}  // namespace rfidray
