#pragma once
// Radio materials. ITU-R P.2040 model: ε' = a·f^b, σ = c·f^d (f in GHz, σ in S/m), complex relative
// permittivity η = ε' − j σ/(ω ε0). Several P.2040 entries are specified from 1 GHz; at 860–960 MHz we
// extrapolate the same power laws (documented; a warning is emitted once per material).
#include <complex>
#include <optional>
#include <string>
#include <vector>

namespace rfidray {

struct RadioMaterial {
  std::string name;
  double a = 1.0, b = 0.0, c = 0.0, d = 0.0;  // P.2040 coefficients
  double thickness_m = 0.0;   // > 0: slab model (reflection and transmission through a layer of this thickness)
  bool perfect_conductor = false;  // metal: Γ = −1 (TE), opaque
  double min_valid_ghz = 0.0;      // below this the P.2040 fit is extrapolated

  double relative_permittivity(double frequency_hz) const;      // ε'
  double conductivity_s_m(double frequency_hz) const;           // σ
  std::complex<double> complex_permittivity(double frequency_hz) const;  // η = ε' − jσ/(ωε0)
  bool extrapolated(double frequency_hz) const { return frequency_hz / 1e9 < min_valid_ghz; }
};

// concrete, brick, plasterboard, wood, glass, metal (P.2040 Table 3). nullopt if unknown.
std::optional<RadioMaterial> builtin_material(const std::string& name);
std::vector<std::string> builtin_material_names();
// A user-defined material with fixed ε' and σ (S/m), optional thickness.
RadioMaterial user_material(const std::string& name, double eps_r, double sigma_s_m, double thickness_m);

}  // namespace rfidray
