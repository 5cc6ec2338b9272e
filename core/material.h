#pragma once
// Radio materials. ITU-R P.2040 (Table 3) model: ε' = a·f^b, σ = c·f^d (f in GHz, σ in S/m), complex relative
// permittivity η = ε' − j σ/(ω ε0) (time dependence e^{jωt}). Table 3 gives each fit a frequency range:
// concrete 1–100 GHz, brick 1–40 GHz, plasterboard 1–100 GHz, wood 0.001–100 GHz, glass 0.1–100 GHz,
// metal 1–100 GHz. So at UHF RFID frequencies (860–960 MHz) concrete, brick and plasterboard are
// extrapolated (same power laws; `extrapolated()` says so, the caller warns once per material), while wood
// and glass are inside their ranges. Metal is treated as a perfect conductor, which does not use the fit.
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
  // The material's faces bound closed solids (a wall modelled as a box, with its end faces and back edges): a
  // direct path's entry into a solid and its exit from it are one slab of the thickness they cut, measured along
  // the entry face's normal (chord · cos θ; exact for parallel faces), so the ITU-R P.2040 slab transmission
  // applies once per pair and the exit face adds nothing; a path leaving by a face more than 45° from its entry
  // face (cutting a corner) is dropped. Reflection off a solid's face uses thickness_m (0: half-space). Crossings
  // of one solid material alternate entry, exit along a path that starts outside.
  bool solid = false;
  double min_valid_ghz = 0.0;      // below this the P.2040 fit is extrapolated
  double max_valid_ghz = 1e300;    // above this too

  double relative_permittivity(double frequency_hz) const;      // ε'
  double conductivity_s_m(double frequency_hz) const;           // σ
  std::complex<double> complex_permittivity(double frequency_hz) const;  // η = ε' − jσ/(ωε0)
  // True when the P.2040 fit is used outside its frequency range (never for a perfect conductor).
  bool extrapolated(double frequency_hz) const {
    return !perfect_conductor && (frequency_hz / 1e9 < min_valid_ghz || frequency_hz / 1e9 > max_valid_ghz);
  }
};

// concrete, brick, plasterboard, wood, glass, metal (P.2040 Table 3) and water (Debye; core/material.cpp).
// nullopt if unknown.
std::optional<RadioMaterial> builtin_material(const std::string& name);
std::vector<std::string> builtin_material_names();
// A user-defined material with fixed ε' and σ (S/m), optional thickness (0: half-space).
// Throws InputError naming the material when ε' is not ≥ 1, σ < 0 or thickness < 0, or any is not finite.
RadioMaterial user_material(const std::string& name, double eps_r, double sigma_s_m, double thickness_m);

}  // namespace rfidray
