#pragma once
// A point on an integer grid (a vertex welded on a 1 µm grid, a cell of 1 m) and its hash, for the unordered maps
// that weld vertices (raytrace/facet.cpp, raytrace/edges.cpp) and bin facets (raytrace/edges.cpp). Value types; the
// hash is a pure function.
#include <cstddef>
#include <cstdint>

namespace rfidray {

struct GridKey {
  int64_t x = 0, y = 0, z = 0;
  bool operator==(const GridKey&) const = default;
};

struct GridHash {
  size_t operator()(const GridKey& k) const {
    // Unsigned arithmetic: wraps instead of overflowing (the keys of georeferenced meshes reach ~1e13). The three
    // combined, then splitmix64's finalizer: keys on an axis-aligned grid (a warehouse's) spread over the buckets.
    uint64_t h = static_cast<uint64_t>(k.x) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<uint64_t>(k.y) + 0xBF58476D1CE4E5B9ull + (h << 6) + (h >> 2);
    h ^= static_cast<uint64_t>(k.z) + 0x94D049BB133111EBull + (h << 6) + (h >> 2);
    h ^= h >> 31;
    h *= 0xBF58476D1CE4E5B9ull;
    h ^= h >> 29;
    return static_cast<size_t>(h);
  }
};

}  // namespace rfidray
