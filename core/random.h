#pragma once
// Deterministic random streams. Every (antenna, tick) draws from its own generator whose seed is
// derived from the run seed and the stream's indices, so results do not depend on thread count.
#include <cstdint>
#include <initializer_list>
#include <random>

namespace rfidray {

using Rng = std::mt19937_64;

// SplitMix64 finaliser (Steele, Lea, Flood 2014): a bijective 64-bit mix, used to decorrelate seeds.
inline uint64_t mix64(uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

inline uint64_t stream_seed(uint64_t run_seed, std::initializer_list<uint64_t> indices) {
  uint64_t s = mix64(run_seed);
  for (uint64_t i : indices) s = mix64(s ^ mix64(i + 0x632be59bd9b4e019ULL));
  return s;
}

inline Rng make_stream(uint64_t run_seed, std::initializer_list<uint64_t> indices) {
  return Rng(stream_seed(run_seed, indices));
}

}  // namespace rfidray
