// Second-order diffraction's edge pairs shared per block of nearby tags (PathFinder::edge_pairs_near, used by
// trace_sum): the block keeps only the orders of edge pairs that can carry a path for some tag of its box, and every
// link then walks those. The bounds must never drop an order the per-link tests would keep, so the channel is the
// same to the bit (the same paths, summed in the same order) as when every link walks every pair: on the paper
// warehouse (rack bays: parallel shelf edges and plate corners) and on random scenes with tags on and next to edges
// and corners. And kAuto shares where blocks are compact and declines where they are not.
#include <gtest/gtest.h>

#include <complex>
#include <random>
#include <vector>

#include "core/units.h"
#include "raytrace/path_finder.h"
#include "raytrace/raytraced_channel.h"
#include "raytrace/warehouse.h"
#include "tests/support/endpoint_at.h"

namespace rfidray {
namespace {

using C = std::complex<double>;
constexpr double kF = 866e6;

using testing::linear_dipole_at;

TraceOptions full_options() {
  TraceOptions o;
  o.level = ChannelLevel::kFull;
  o.drop_below_db = 80.0;
  return o;
}

struct Compared {
  size_t links = 0, second_order_paths = 0;
  double orders_shared = 0.0, orders_every = 0.0;  // tl_edge_pair_orders_tried per link
};

// trace_sum over `tags` in the given order (blocks of 16 consecutive tags), shared and not: h equal to the bit.
Compared compare_shared(const PathFinder& finder, const std::vector<Endpoint>& antennas,
                        const std::vector<Endpoint>& tags) {
  Compared r;
  std::vector<uint32_t> which(tags.size());
  for (uint32_t i = 0; i < which.size(); ++i) which[i] = i;
  std::vector<C> every(tags.size()), shared(tags.size());
  std::vector<TracedPath> paths;
  for (const Endpoint& a : antennas) {
    PoseCandidates c;
    finder.prepare_pose(a.pose.position, c);
    c.share_edge_pairs = false;
    tl_edge_pair_orders_tried = 0;
    finder.trace_sum(a, tags, which, kF, c, 1, every);
    r.orders_every += static_cast<double>(tl_edge_pair_orders_tried);
    c.share_edge_pairs = true;
    tl_edge_pair_orders_tried = 0;
    finder.trace_sum(a, tags, which, kF, c, 1, shared);
    r.orders_shared += static_cast<double>(tl_edge_pair_orders_tried);
    for (size_t i = 0; i < tags.size(); ++i) {
      EXPECT_EQ(shared[i], every[i]) << "antenna " << a.pose.position.transpose() << " tag "
                                     << tags[i].pose.position.transpose();
      finder.trace(a, tags[i], kF, c, paths);
      for (const TracedPath& p : paths) r.second_order_paths += p.kind == PathKind::kDiffraction2;
    }
    r.links += tags.size();
  }
  r.orders_shared /= static_cast<double>(r.links);
  r.orders_every /= static_cast<double>(r.links);
  return r;
}

// Compact patches of tags (a block of 16 is one patch: 4 × 4) on and in front of the paper warehouse's rack faces.
std::vector<Endpoint> rack_patches() {
  std::vector<Endpoint> tags;
  for (double y0 : {-3.4, -0.2, 4.1})
    for (double x : {2.90, 2.75, -4.85})
      for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
          tags.push_back(linear_dipole_at(Vec3(x, y0 + 0.1 * i, 0.95 + 0.12 * j), Vec3::UnitZ()));
  return tags;
}

TEST(EdgePairSharing, BlockOrdersGiveEveryLinksChannelOnThePaperWarehouse) {
  const auto scene = std::make_shared<const Scene>(paper_warehouse_meshes(), MaterialAssignment{});
  const PathFinder finder(scene, full_options());
  std::vector<Endpoint> antennas;
  for (double y : {-3.0, 1.0, 5.0}) antennas.push_back(linear_dipole_at(Vec3(0.5, y, 1.68), Vec3::UnitZ()));
  const Compared r = compare_shared(finder, antennas, rack_patches());
  EXPECT_GT(r.second_order_paths, 200u);  // the pairs the bounds judge really carry paths
  // Shared, a link walks a small part of the orders (each of 16 tags 0.1–0.36 m apart).
  EXPECT_LT(r.orders_shared, 0.3 * r.orders_every) << r.orders_shared << " of " << r.orders_every;
}

TEST(EdgePairSharing, BlockOrdersGiveEveryLinksChannelInRandomScenes) {
  // Random axis-aligned boxes (corners where three edges meet), thin plates (parallel pairs sharing a face) and one
  // tilted plate; blocks of tags spread out, compact, on an edge's line, at a corner and just off a face.
  std::mt19937 rng(20261207);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int scene_index = 0; scene_index < 3; ++scene_index) {
    TriangleMesh m;
    m.name = "random";
    m.material_names = {"metal"};
    add_quad(m, Vec3(-4, -4, 0), Vec3(8, 0, 0), Vec3(0, 8, 0), 0, 1, 1);  // floor
    std::vector<Vec3> corners;
    for (int b = 0; b < 5; ++b) {
      const Vec3 lo(-3 + 5 * u(rng), -3 + 5 * u(rng), std::round(4 * u(rng)) * 0.25);
      const Vec3 size(0.2 + 0.8 * u(rng), 0.2 + 0.8 * u(rng), 0.05 + 0.6 * u(rng));
      add_box(m, lo, lo + size, 0, 1, true);
      corners.push_back(lo + size);
    }
    for (int p = 0; p < 3; ++p) {  // shelf plates 0.3 m apart
      const Vec3 c(-3 + 5 * u(rng), -3 + 5 * u(rng), 0.6);
      add_quad(m, c, Vec3(0.8, 0, 0), Vec3(0, 0.4, 0), 0, 1, 1);
      add_quad(m, c + Vec3(0, 0, 0.3), Vec3(0.8, 0, 0), Vec3(0, 0.4, 0), 0, 1, 1);
      corners.push_back(c);
    }
    add_quad(m, Vec3(2.5, -2, 0.3), Vec3(0.7, 0.5, 0), Vec3(0, 0, 1.0), 0, 1, 1);  // tilted about z
    const auto scene = std::make_shared<const Scene>(std::vector<TriangleMesh>{m}, MaterialAssignment{});
    const PathFinder finder(scene, full_options());
    std::vector<Endpoint> antennas;
    for (int i = 0; i < 2; ++i)
      antennas.push_back(
          linear_dipole_at(Vec3(-3.5 + 7 * u(rng), -3.5 + 7 * u(rng), 0.3 + 2.0 * u(rng)), Vec3::UnitZ()));
    std::vector<Endpoint> tags;
    for (int i = 0; i < 32; ++i)  // two blocks anywhere
      tags.push_back(
          linear_dipole_at(Vec3(-3.8 + 7.6 * u(rng), -3.8 + 7.6 * u(rng), 0.05 + 2.0 * u(rng)), Vec3(u(rng), 0, 1)));
    for (const Vec3& corner : corners)  // a block round each corner: at it, on its edges' lines, 1 mm and 5 cm off
      for (int i = 0; i < 16; ++i) {
        Vec3 p = corner;
        const int axis = i % 3;
        if (i == 0) {
        } else if (i < 7) {
          p[axis] += (i < 4 ? 0.05 : -0.02) * (1.0 + u(rng));
        } else {
          p += Vec3(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5) * (i < 12 ? 2e-3 : 0.1);
        }
        tags.push_back(linear_dipole_at(p, Vec3(1, u(rng), 0.5)));
      }
    for (int i = 0; i < 16; ++i)  // a compact patch in the open
      tags.push_back(linear_dipole_at(Vec3(0.1 * (i % 4), 0.1 * (i / 4), 1.3), Vec3::UnitZ()));
    SCOPED_TRACE(::testing::Message() << "scene " << scene_index);
    const Compared r = compare_shared(finder, antennas, tags);
    EXPECT_GT(r.second_order_paths, 20u);
    EXPECT_LT(r.orders_shared, r.orders_every);
  }
}

TEST(EdgePairSharing, AutoSharesCompactBlocksAndDeclinesScatteredOnes) {
  const auto scene = std::make_shared<const Scene>(paper_warehouse_meshes(), MaterialAssignment{});
  const auto orders_per_link = [&](TraceOptions::Sharing sharing, const std::vector<Endpoint>& tags) {
    TraceOptions o = full_options();
    o.edge_pair_sharing = sharing;
    const RaytracedChannel channel(scene, o);
    std::vector<C> h(tags.size());
    tl_edge_pair_orders_tried = 0;
    channel.one_way(linear_dipole_at(Vec3(0.5, 0.0, 1.68), Vec3::UnitZ()), tags, kF, h);
    return static_cast<double>(tl_edge_pair_orders_tried) / static_cast<double>(tags.size());
  };
  // 64 tags 2.5 cm apart on one rack face: compact blocks, few orders kept.
  std::vector<Endpoint> compact;
  for (int i = 0; i < 64; ++i)
    compact.push_back(linear_dipole_at(Vec3(2.90, -0.2 + 0.025 * (i % 8), 1.0 + 0.025 * (i / 8)), Vec3::UnitZ()));
  const double every = orders_per_link(TraceOptions::Sharing::kNever, compact);
  EXPECT_LT(orders_per_link(TraceOptions::Sharing::kAuto, compact), 0.3 * every);
  // 64 tags scattered over the whole hall: a block's box spans it, the probe keeps most orders and declines.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Endpoint> scattered;
  for (int i = 0; i < 64; ++i)
    scattered.push_back(
        linear_dipole_at(Vec3(-6.0 + 12.0 * u(rng), -10.0 + 20.0 * u(rng), 0.2 + 2.5 * u(rng)), Vec3::UnitZ()));
  EXPECT_EQ(orders_per_link(TraceOptions::Sharing::kAuto, scattered),
            orders_per_link(TraceOptions::Sharing::kNever, scattered));
  // Too few tags for a probe to pay: never shared.
  compact.resize(48);
  EXPECT_EQ(orders_per_link(TraceOptions::Sharing::kAuto, compact), every);
}

}  // namespace
}  // namespace rfidray
