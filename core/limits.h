#pragma once
// The physically meaningful ranges of rfidray's inputs (README, "Limits and errors"). Each is checked where
// the value enters (scenario YAML, SDF world, command line, mesh files) with the field named, so that no
// overflow, NaN or unbounded allocation reaches the physics, the ray tracer or an output file.
#include <cmath>
#include <cstdio>
#include <string>

#include "core/error.h"
#include "core/number_text.h"

namespace rfidray::limits {

inline constexpr double kMinFrequencyHz = 1e6;     // 1 MHz
inline constexpr double kMaxFrequencyHz = 100e9;   // 100 GHz
inline constexpr double kMaxPowerDbm = 100.0;      // |tx power|, sensitivities: within ±100 dBm
inline constexpr double kMaxGainDbi = 100.0;       // |antenna / tag gain| within ±100 dBi
inline constexpr double kMaxNoiseRssiDb = 100.0;   // RSSI noise σ (physical model), dB
inline constexpr double kMaxNoisePhaseRad = 1e3;   // phase noise σ, rad
inline constexpr double kMaxNoiseRssiLinear = 1e6; // paper model's n_RSSI σ (linear amplitude units)
// Positions and mesh vertices: |x|, |y|, |z| ≤ 1e8 m (covers UTM / ECEF coordinates; scenes far from the
// origin are re-centred about their bounding-box centre before the float BVH, so they keep their accuracy).
inline constexpr double kMaxCoordinateM = 1e8;
// Simulated ticks per antenna (duration × update rate): at most 1e9.
inline constexpr double kMaxTicks = 1e9;
// Triangles of one scene (a generated warehouse, or all meshes loaded): at most 2e8 (≈ 40 GB of BVH).
inline constexpr double kMaxTriangles = 2e8;

// "field 'F': must be in [lo, hi] UNIT (got v)"
inline void check_range(double v, double lo, double hi, const std::string& field, const char* unit) {
  if (!(std::isfinite(v) && v >= lo && v <= hi))
    throw field_error(field, std::string(std::isfinite(v) ? "must be in [" : "must be a finite number in [") + num(lo) +
                                 ", " + num(hi) + "] " + unit + " (got " + num(v) + ")");
}

inline bool coordinate_ok(double v) { return std::isfinite(v) && std::abs(v) <= kMaxCoordinateM; }

}  // namespace rfidray::limits
