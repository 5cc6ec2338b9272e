#include "core/material.h"

#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/units.h"

namespace rfidray {
namespace {

RadioMaterial itu(const char* name, double a, double b, double c, double d, double min_ghz, double max_ghz) {
  RadioMaterial m;
  m.name = name;
  m.a = a;
  m.b = b;
  m.c = c;
  m.d = d;
  m.min_valid_ghz = min_ghz;
  m.max_valid_ghz = max_ghz;
  return m;
}

// ITU-R P.2040 Table 3: name, a, b, c, d, valid frequency range (GHz).
std::vector<RadioMaterial> table() {
  std::vector<RadioMaterial> t = {
      itu("concrete", 5.24, 0.0, 0.0462, 0.7822, 1.0, 100.0),
      itu("brick", 3.91, 0.0, 0.0238, 0.16, 1.0, 40.0),
      itu("plasterboard", 2.73, 0.0, 0.0085, 0.9395, 1.0, 100.0),
      itu("wood", 1.99, 0.0, 0.0047, 1.0718, 0.001, 100.0),
      itu("glass", 6.31, 0.0, 0.0036, 1.3394, 0.1, 100.0),
      itu("metal", 1.0, 0.0, 1e7, 0.0, 1.0, 100.0),
  };
  t.back().perfect_conductor = true;
  // Not in P.2040: fresh water at 25 °C, Debye relaxation (Kaatze, J. Chem. Eng. Data 34, 1989: ε_s = 78.36,
  // ε_∞ = 5.2, τ = 8.27 ps) in the same power-law form. For ωτ ≪ 1, ε' ≈ ε_s and σ = ωε0ε'' ≈ ε0(ε_s − ε_∞)τω²:
  // ε' = 78.2, σ = 0.211·f² (f in GHz; 0.158 S/m at 866 MHz), within 3 % of the Debye values from 0.1 to 3 GHz.
  // Salt raises σ (tap water adds ~0.01–0.05 S/m); give a user material for it.
  t.push_back(itu("water", 78.2, 0.0, 0.211, 2.0, 0.1, 3.0));
  return t;
}

}  // namespace

double RadioMaterial::relative_permittivity(double frequency_hz) const {
  return a * std::pow(frequency_hz / 1e9, b);
}

double RadioMaterial::conductivity_s_m(double frequency_hz) const { return c * std::pow(frequency_hz / 1e9, d); }

std::complex<double> RadioMaterial::complex_permittivity(double frequency_hz) const {
  // P.2040 eq. (9b): η = ε' − j σ/(ω ε0), ω = 2πf.
  const double omega = kTwoPi * frequency_hz;
  return {relative_permittivity(frequency_hz), -conductivity_s_m(frequency_hz) / (omega * kVacuumPermittivity_F_m)};
}

std::optional<RadioMaterial> builtin_material(const std::string& name) {
  for (RadioMaterial& m : table())
    if (m.name == name) return m;
  return std::nullopt;
}

std::vector<std::string> builtin_material_names() {
  std::vector<std::string> names;
  for (const RadioMaterial& m : table()) names.push_back(m.name);
  return names;
}

RadioMaterial user_material(const std::string& name, double eps_r, double sigma_s_m, double thickness_m) {
  const std::string field = "materials." + name;
  auto str = [](double v) {
    std::ostringstream os;
    os << v;
    return os.str();
  };
  if (!(std::isfinite(eps_r) && eps_r >= 1.0))
    throw field_error(field + ".eps_r", "relative permittivity must be finite and >= 1 (got " + str(eps_r) + ")");
  if (!(std::isfinite(sigma_s_m) && sigma_s_m >= 0.0))
    throw field_error(field + ".sigma", "conductivity must be finite and >= 0 S/m (got " + str(sigma_s_m) + ")");
  if (!(std::isfinite(thickness_m) && thickness_m >= 0.0))
    throw field_error(field + ".thickness", "must be finite and >= 0 m (got " + str(thickness_m) + ")");
  RadioMaterial m;
  m.name = name;
  m.a = eps_r;
  m.c = sigma_s_m;
  m.thickness_m = thickness_m;
  return m;
}

}  // namespace rfidray
