#pragma once
// The ray-traced channel: h = Σ_paths coefficient_i · λ/(4πL_i) · e^{−jkL_i} over the paths PathFinder finds
// (raytrace/path_finder.h documents the physics). Levels: los, los+blocked, single-bounce.
// Thread-safe: the scene is read-only and every call keeps its scratch on the calling thread.
#include <memory>

#include "core/channel.h"
#include "raytrace/path_finder.h"

namespace rfidray {

class RaytracedChannel final : public Channel {
 public:
  RaytracedChannel(std::shared_ptr<const Scene> scene, const TraceOptions& options = {});

  std::string name() const override { return to_string(finder_.options().level); }
  std::vector<Path> paths(const Endpoint& antenna, const Endpoint& tag, double frequency_hz) const override;
  // One candidate search per call (per antenna pose), shared by all tags; OpenMP over tags when not already
  // inside a parallel region.
  void one_way(const Endpoint& antenna, std::span<const Endpoint> tags, double frequency_hz,
               std::span<std::complex<double>> h) const override;

  const PathFinder& finder() const { return finder_; }
  const Scene& scene() const { return finder_.scene(); }

 private:
  PathFinder finder_;
};

}  // namespace rfidray
