// Conics of the hyperbolic method against closed-form geometry.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "localization/hyperbola.h"
#include "localization/hyperbolic.h"
#include "core/units.h"

namespace rfidray::loc {
namespace {

TEST(Hyperbola, PlaneSectionIsTheClosedFormHyperbola) {
  // Foci (±c, 0) in the plane itself, Δr = 2a > 0: x²/a² − y²/b² = 1, b² = c² − a², on the branch x < 0
  // (|x − F2| > |x − F1| means nearer F1 = (−c, 0)).
  const double c = 1.0, a = 0.4, b2 = c * c - a * a, h = 1.5;
  const Hyperbola hyp{Vec3(-c, 0, h), Vec3(c, 0, h), 2 * a};
  int points = 0;
  for (int i = 0; i < 360; ++i)
    for (int slot = 0; slot < 2; ++slot) {
      Vec3 p;
      if (!point_on_ray(hyp, h, kTwoPi * i / 360, slot, p)) continue;
      ++points;
      EXPECT_NEAR(p.x() * p.x() / (a * a) - p.y() * p.y() / b2, 1.0, 1e-9);
      EXPECT_LT(p.x(), 0.0);
      EXPECT_NEAR(residual(hyp, p), 0.0, 1e-9);
    }
  EXPECT_GT(points, 100);
}

TEST(Hyperbola, SectionOfPlaneAboveFociSatisfies3dLocus) {
  // Foci at 1.68 m and 1.2 m, tag plane at 2.05 m: every section point satisfies the 3-D distance difference.
  const Hyperbola hyp{Vec3(-1, -2, 1.68), Vec3(-0.5, 1, 1.2), 0.7};
  const PlaneSection s = sample_section(hyp, 2.05, 720, 20.0);
  int n = 0;
  for (size_t i = 0; i < s.points.size(); ++i)
    if (s.valid(static_cast<int>(i))) {
      ++n;
      EXPECT_NEAR(s.points[i].z(), 2.05, 0);
      EXPECT_NEAR(residual(hyp, s.points[i]), 0.0, 1e-8);
    }
  EXPECT_GT(n, 50);
}

TEST(Hyperbola, IntersectionOfTwoConicsThroughATagContainsTagAndMirror) {
  // Three collinear antenna positions (a straight path along y): the intersections are the tag and its
  // reflection across the path line, exactly.
  const Vec3 tag(2.3, 0.7, 2.05);
  const Vec3 p0(-1, -2, 1.68), p1(-1, 0, 1.68), p2(-1, 2.5, 1.68);
  auto conic = [&](const Vec3& f2) { return Hyperbola{p0, f2, (tag - f2).norm() - (tag - p0).norm(), 0.0}; };
  const Hyperbola h1 = conic(p1), h2 = conic(p2);
  const auto pts = intersect_in_plane(h2, sample_section(h2, tag.z(), 720, 20.0), h1);
  const Vec3 mirror(-1 - (tag.x() + 1), tag.y(), tag.z());
  bool found_tag = false, found_mirror = false;
  for (const Vec3& p : pts) {
    EXPECT_NEAR(residual(h1, p), 0.0, 1e-8);
    EXPECT_NEAR(residual(h2, p), 0.0, 1e-8);
    found_tag |= (p - tag).norm() < 1e-7;
    found_mirror |= (p - mirror).norm() < 1e-7;
  }
  EXPECT_TRUE(found_tag);
  EXPECT_TRUE(found_mirror);
}

TEST(Hyperbola, ConicsOfDifferentSegmentsMeetAtTheTagToo) {
  // The section keeps its distances to its own F1 and reuses them for conics with the same F1 (one unwrapped
  // segment); conics of another segment have another F1 and take both distances afresh. Both must give the
  // tag, and the shared case the same points as computing both distances.
  const Vec3 tag(2.3, 0.7, 2.05);
  const Vec3 p0(-1, -2, 1.68), p1(-1, 0, 1.68), q0(-0.8, -1.5, 1.3), q1(-0.7, 1.8, 1.3);
  auto conic = [&](const Vec3& f1, const Vec3& f2) {
    return Hyperbola{f1, f2, (tag - f2).norm() - (tag - f1).norm(), 0.0};
  };
  const Hyperbola a = conic(p0, p1), b = conic(q0, q1), a2 = conic(p0, q1);
  const PlaneSection s = sample_section(a, tag.z(), 720, 20.0);
  auto has_tag = [&](const std::vector<Vec3>& pts) {
    bool found = false;
    for (const Vec3& p : pts) found |= (p - tag).norm() < 1e-7;
    return found;
  };
  EXPECT_TRUE(has_tag(intersect_in_plane(a, s, b)));  // different F1
  const std::vector<Vec3> shared = intersect_in_plane(a, s, a2);  // same F1
  EXPECT_TRUE(has_tag(shared));
  // The same conic with a copy of F1 that differs in the last bit takes the unshared branch.
  Hyperbola a2_moved = a2;
  a2_moved.f1.x() = std::nextafter(a2.f1.x(), 0.0);
  a2_moved.delta_m = (tag - a2_moved.f2).norm() - (tag - a2_moved.f1).norm();
  const std::vector<Vec3> unshared = intersect_in_plane(a, s, a2_moved);
  ASSERT_EQ(shared.size(), unshared.size());
  for (size_t i = 0; i < shared.size(); ++i) EXPECT_LT((shared[i] - unshared[i]).norm(), 1e-9);
}

TEST(Hyperbola, ThreeHyperboloidsMeetAtTheTag) {
  const Vec3 tag(1.5, 0.5, 2.4);
  const Vec3 r(-1, -2, 0.6);
  auto conic = [&](const Vec3& f2) { return Hyperbola{r, f2, (tag - f2).norm() - (tag - r).norm(), 0.0}; };
  Vec3 out;
  ASSERT_TRUE(intersect_3d(conic(Vec3(-1, 0, 2.0)), conic(Vec3(-1, 2, 0.8)), conic(Vec3(1, 3, 1.4)),
                           tag + Vec3(0.3, -0.2, -0.3), out));
  EXPECT_LT((out - tag).norm(), 1e-9);
}

TEST(Hyperbola, QualityIsInverseGdop) {
  // Orthogonal unit gradients: (JᵀJ)⁻¹ = I → GDOP = √2.
  EXPECT_NEAR(intersection_quality({Vec3(1, 0, 0), Vec3(0, 1, 0)}, true), 1 / std::sqrt(2.0), 1e-12);
  // Gradients at 30°: det = sin 30°, trace((JᵀJ)⁻¹) = 2 / sin² 30° → quality = sin 30° / √2.
  const double s = std::sin(kPi / 6);
  EXPECT_NEAR(intersection_quality({Vec3(1, 0, 0), Vec3(std::cos(kPi / 6), s, 0)}, true), s / std::sqrt(2.0), 1e-12);
  // Parallel: no fix.
  EXPECT_EQ(intersection_quality({Vec3(1, 0, 0), Vec3(2, 0, 0)}, true), 0.0);
}

TEST(Hyperbola, GradientNormIsTwiceSineOfHalfAngle) {
  const Hyperbola h{Vec3(0, 0, 0), Vec3(2, 0, 0), 0.0};
  const Vec3 x(1, 1, 0);  // F1–x–F2 is a right angle
  EXPECT_NEAR(gradient(h, x).norm(), 2 * std::sin(kPi / 4), 1e-12);
}

TEST(Hyperbola, ModesFindDenseWeightedCluster) {
  std::vector<Intersection> set;
  for (int i = 0; i < 50; ++i) set.push_back({Vec3(1 + 0.001 * (i % 5), 2 - 0.001 * (i % 7), 0), 1.0, 0, 0, 0});
  for (int i = 0; i < 10; ++i) set.push_back({Vec3(5 + 0.3 * i, -3, 0), 1.0, 0, 0, 0});
  const auto modes = intersection_modes(set, 0.05, 3);
  ASSERT_FALSE(modes.empty());
  EXPECT_LT((modes[0] - Vec3(1.002, 1.997, 0)).norm(), 0.003);
}

TEST(Hyperbola, BlockedSignSearchGivesBitwiseTheSamePointsAsEverySample) {
  // intersect_in_plane skips blocks of samples that a Lipschitz bound proves free of sign changes. Whatever
  // the block sizes, the points must be bitwise those of evaluating every sample (blocks of 1), including
  // where two crossings are close (tags near the antenna path, whose mirror crossing is near the tag) and
  // for conics of another segment (different F1). Stage-like foci on a line and random foci in space.
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  int pairs = 0, points = 0, close_pairs = 0;
  std::vector<Vec3> every, blocked;
  for (int trial = 0; trial < 300; ++trial) {
    const bool line = trial % 2 == 0;
    auto focus = [&]() {
      return line ? Vec3(u(rng), 0.0, 0.0) : Vec3(2 * u(rng) - 1, 2 * u(rng) - 1, u(rng) - 0.5);
    };
    // Tags from 1 mm to 3 m off the path: the nearest ones put the tag and its mirror crossing close.
    const Vec3 tag(2 * u(rng) - 0.5, std::pow(10.0, -3.0 + 3.5 * u(rng)), trial % 3 == 0 ? 0.0 : u(rng) - 0.5);
    const Vec3 f1 = focus(), f2 = focus(), g1 = trial % 4 == 1 ? focus() : f1, g2 = focus();
    auto conic = [&](const Vec3& a, const Vec3& b) { return Hyperbola{a, b, (tag - b).norm() - (tag - a).norm(), 0.0}; };
    const Hyperbola h1 = conic(f1, f2), h2 = conic(g1, g2);
    if (!h1.valid() || !h2.valid()) continue;
    const PlaneSection s = sample_section(h1, tag.z(), 720, 3.0 + 10.0 * u(rng));
    intersect_in_plane(h1, s, h2, every, 1, 1);
    ++pairs;
    points += static_cast<int>(every.size());
    for (size_t i = 0; i + 1 < every.size(); ++i)
      for (size_t j = i + 1; j < every.size(); ++j) close_pairs += (every[i] - every[j]).norm() < 0.02;
    for (const auto& [coarse, fine] : {std::pair{32, 8}, std::pair{128, 2}, std::pair{7, 3}, std::pair{5, 5}}) {
      intersect_in_plane(h1, s, h2, blocked, coarse, fine);
      ASSERT_EQ(blocked.size(), every.size()) << "trial " << trial << ", blocks " << coarse << "/" << fine;
      for (size_t i = 0; i < every.size(); ++i)
        for (int c = 0; c < 3; ++c)
          ASSERT_EQ(blocked[i][c], every[i][c]) << "trial " << trial << ", blocks " << coarse << "/" << fine;
    }
  }
  // The cases above occurred: most pairs are valid, they cross, and some crossings lie within 2 cm.
  EXPECT_GT(pairs, 200);
  EXPECT_GT(points, pairs);
  EXPECT_GT(close_pairs, 5);
}

}  // namespace
}  // namespace rfidray::loc
