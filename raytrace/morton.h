#pragma once
// Morton (Z-order) keys: points close in space get close keys, so sorting by key gives a traversal order with
// coherent rays and warm caches.
#include <algorithm>
#include <cstdint>

#include "core/geometry.h"

namespace rfidray {

// Interleaved bits of the position on a 0.25 m grid (21 bits per axis, offset so negative coordinates sort).
inline uint64_t morton_key(const Vec3& p) {
  auto spread = [](double x) {
    uint64_t v = static_cast<uint64_t>(std::clamp(x / 0.25 + 1048576.0, 0.0, 2097151.0));
    v = (v | v << 32) & 0x1f00000000ffffULL;
    v = (v | v << 16) & 0x1f0000ff0000ffULL;
    v = (v | v << 8) & 0x100f00f00f00f00fULL;
    v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
    v = (v | v << 2) & 0x1249249249249249ULL;
    return v;
  };
  return spread(p.x()) | spread(p.y()) << 1 | spread(p.z()) << 2;
}

}  // namespace rfidray
