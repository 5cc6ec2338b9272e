#pragma once
// The channel interface: everything between the reader antenna's port and the tag's port.
// The ideal channel (free space, paper) and the ray-traced channels (raytrace/) implement it.
#include <complex>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "core/antenna_pattern.h"
#include "core/edge_sight.h"
#include "core/geometry.h"
#include "core/material.h"
#include "core/obstacle_sight.h"
#include "core/path.h"
#include "core/polarization.h"

namespace rfidray {

// The surface nearest to a point, as a tag's mount sees it (core/tag_antenna.h, TagMountSpec::kScene).
struct NearbySurface {
  double distance_m = 0.0;
  RadioMaterial material;  // its radio material (perfect_conductor: metal)
  // The smaller in-plane size of the planar facet it lies on (m): whether the surface is a plane to the tag
  // (a shelf's 3 cm front edge is not one to a 16 cm dipole). Infinity when unknown.
  double facet_extent_m = 1e300;
  // True when the nearest point is the foot of the perpendicular on the facet (the point faces the facet), false
  // when it lies on the facet's border (the point is beyond an edge): a plane model then does not describe it.
  bool faces_facet = true;
};

// One end of a link: where it is, which way it points, how it radiates.
struct Endpoint {
  Pose pose;
  AntennaPattern pattern;
  Polarization polarization;
};

class Channel {
 public:
  virtual ~Channel() = default;
  virtual std::string name() const = 0;

  // Every path of one link, with `contribution` filled (noise-free). Used by `rfidray link`.
  virtual std::vector<Path> paths(const Endpoint& antenna, const Endpoint& tag, double frequency_hz) const = 0;

  // One-way channels h for one antenna pose and many tags (the batch lets a ray tracer share the
  // candidate search of one antenna pose among all tags). Must be thread-safe; h.size() == tags.size().
  virtual void one_way(const Endpoint& antenna, std::span<const Endpoint> tags, double frequency_hz,
                       std::span<std::complex<double>> h) const {
    for (size_t i = 0; i < tags.size(); ++i) h[i] = sum_paths(paths(antenna, tags[i], frequency_hz));
  }

  // The fewest tags for which one_way, called outside a parallel region, splits the batch over every thread;
  // SIZE_MAX: never (the caller then spreads its batches over the threads instead).
  virtual size_t threaded_batch_min_tags() const { return std::numeric_limits<size_t>::max(); }

  // True when the channel depends on nothing but the two endpoints (no moving scene objects), so
  // a link whose endpoints did not move can reuse its last value.
  virtual bool cacheable() const { return true; }

  // The scene's surface nearest to `point` within `max_distance_m`, for tags whose mount comes from the scene;
  // std::nullopt without a scene or when none is that close. Thread-safe.
  virtual std::optional<NearbySurface> nearest_surface(const Vec3& point, double max_distance_m) const {
    (void)point;
    (void)max_distance_m;
    return std::nullopt;
  }

  // The scene's nearest diffracting edge (a wedge or a sheet's free edge) to `end` within `max_distance_m`, as
  // `end` sees it lit from `other_end` and its polarization (core/edge_sight.h): where ray optics near an edge is judged
  // (core/level_validity.h). std::nullopt without a scene or when none is that close. Thread-safe.
  virtual std::optional<EdgeSight> nearest_edge(const Endpoint& end, const Endpoint& other_end,
                                                double max_distance_m) const {
    (void)end;
    (void)other_end;
    (void)max_distance_m;
    return std::nullopt;
  }

  // What the link antenna–tag sees beyond its nearest edge (core/obstacle_sight.h): a narrow obstacle on or beside
  // its direct line, a penetrable slab crossed near the slab's edge, parallel metal plates an end sits between;
  // judged by core/level_validity.h. Empty without a scene. Thread-safe.
  virtual ObstacleSight obstacle_sight(const Endpoint& antenna, const Endpoint& tag, double frequency_hz) const {
    (void)antenna;
    (void)tag;
    (void)frequency_hz;
    return {};
  }
};

// Free space, line of sight always: h = √(G_R G_T) · λ/(4πD) · e^{-jkD} with the pattern gains in the
// LoS direction. Polarization is taken as matched (the paper's model has none).
class IdealChannel final : public Channel {
 public:
  std::string name() const override { return "ideal"; }
  std::vector<Path> paths(const Endpoint& antenna, const Endpoint& tag, double frequency_hz) const override;
  void one_way(const Endpoint& antenna, std::span<const Endpoint> tags, double frequency_hz,
               std::span<std::complex<double>> h) const override;
};

}  // namespace rfidray
