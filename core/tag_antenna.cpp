#include "core/tag_antenna.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "core/dielectric_half_space.h"
#include "core/error.h"
#include "core/fresnel.h"
#include "core/number_text.h"
#include "core/units.h"

namespace rfidray {
namespace {

bool finite_positive(double v) { return std::isfinite(v) && v > 0.0; }

// Power-wave reflection coefficient of a load Z_l on a source Z_s (Kurokawa 1965).
std::complex<double> power_wave_reflection(std::complex<double> z_load, std::complex<double> z_source) {
  return (z_load - std::conj(z_source)) / (z_load + z_source);
}

}  // namespace

std::complex<double> antenna_free_space_impedance(const TagAntennaSpec& antenna, double frequency_hz,
                                                  const std::string& field) {
  switch (antenna.kind) {
    case TagAntennaSpec::Kind::kDipole:
      return dipole_input_impedance(antenna.dipole, frequency_hz);
    case TagAntennaSpec::Kind::kTable: {
      const auto& t = antenna.table;
      if (t.empty()) throw field_error(field + ".table", "has no rows");
      if (frequency_hz <= t.front().frequency_hz) return t.front().impedance_ohm;
      if (frequency_hz >= t.back().frequency_hz) return t.back().impedance_ohm;
      const auto hi = std::upper_bound(t.begin(), t.end(), frequency_hz,
                                       [](double f, const TagAntennaSpec::Point& p) { return f < p.frequency_hz; });
      const auto lo = hi - 1;
      const double w = (frequency_hz - lo->frequency_hz) / (hi->frequency_hz - lo->frequency_hz);
      return (1.0 - w) * lo->impedance_ohm + w * hi->impedance_ohm;
    }
    case TagAntennaSpec::Kind::kNone:
      break;
  }
  throw field_error(field, "the paper's point tag has no impedance (give the tag an antenna: dipole or table)");
}

std::complex<double> antenna_impedance_in_place(const TagAntennaSpec& antenna, const RadioMaterial* material,
                                                double distance_m, double frequency_hz, const std::string& field) {
  if (!material || !(distance_m > 0.0) || antenna.kind != TagAntennaSpec::Kind::kDipole)
    return antenna_free_space_impedance(antenna, frequency_hz, field);
  if (!(distance_m >= antenna.dipole.radius_m))
    throw field_error(field + ".distance_m", "must be at least the wire's radius (" +
                                                 num(antenna.dipole.radius_m) + " m; got " + num(distance_m) + ")");
  if (material->perfect_conductor) {
    const auto plane = perfect_conductor_plane(distance_m, frequency_hz);
    return dipole_input_impedance(antenna.dipole, frequency_hz, plane.get());
  }
  const auto half_space = dielectric_half_space(distance_m, frequency_hz, material->complex_permittivity(frequency_hz),
                                                antenna.dipole.length_m);
  return dipole_input_impedance(antenna.dipole, frequency_hz, half_space.get());
}

std::complex<double> chip_impedance(const TagChipSpec& chip, const TagAntennaSpec& antenna, double frequency_hz,
                                    const std::string& field) {
  const double omega = kTwoPi * frequency_hz;
  switch (chip.kind) {
    case TagChipSpec::Kind::kMatched: {
      const double f = chip.design_frequency_hz > 0.0 ? chip.design_frequency_hz : frequency_hz;
      return std::conj(antenna_free_space_impedance(antenna, f, field));
    }
    case TagChipSpec::Kind::kSeries:
      return {chip.resistance_ohm, -1.0 / (omega * chip.capacitance_f)};
    case TagChipSpec::Kind::kParallel: {
      const std::complex<double> y(1.0 / chip.resistance_ohm, omega * chip.capacitance_f);
      return 1.0 / y;
    }
  }
  throw field_error(field, "unknown chip kind");
}

TagCoupling tag_coupling(std::complex<double> z_free_ohm, std::complex<double> z_in_place_ohm,
                         std::complex<double> z_chip_ohm) {
  TagCoupling c;
  c.free_space_impedance_ohm = z_free_ohm;
  c.antenna_impedance_ohm = z_in_place_ohm;
  c.chip_impedance_ohm = z_chip_ohm;
  const double r_a0 = z_free_ohm.real(), r_a = z_in_place_ohm.real(), r_c = z_chip_ohm.real();
  const double sum2 = std::norm(z_in_place_ohm + z_chip_ohm);
  c.power_transfer = 4.0 * r_c * r_a / sum2;
  c.chip_power_factor = 4.0 * r_a0 * r_c / sum2;
  // Backscatter: absorbing state Z_c, modulating state a short.
  const std::complex<double> d_rho = power_wave_reflection(z_chip_ohm, z_in_place_ohm) -
                                     power_wave_reflection(0.0, z_in_place_ohm);
  const std::complex<double> d_rho_free = power_wave_reflection(z_chip_ohm, z_free_ohm) -
                                          power_wave_reflection(0.0, z_free_ohm);
  const double gain_ratio = r_a0 / r_a;
  c.modulation_factor = gain_ratio * gain_ratio * std::norm(d_rho) / 4.0;
  c.backscatter_phase_rad = std::arg(d_rho / d_rho_free);
  return c;
}

TagCoupling tag_coupling(const TagAntennaSpec& antenna, const TagChipSpec& chip, const RadioMaterial* material,
                         double distance_m, double frequency_hz, const std::string& field) {
  const std::complex<double> z_free = antenna_free_space_impedance(antenna, frequency_hz, field + ".antenna");
  const std::complex<double> z_in = antenna_impedance_in_place(antenna, material, distance_m, frequency_hz,
                                                               field + ".backing");
  const std::complex<double> z_chip = chip_impedance(chip, antenna, frequency_hz, field + ".chip");
  if (!(z_free.real() > 0.0 && z_in.real() > 0.0 && z_chip.real() > 0.0))
    throw field_error(field, "the antenna's and the chip's resistances must be > 0 (antenna " + num(z_in.real()) +
                                 " Ω, chip " + num(z_chip.real()) + " Ω)");
  return tag_coupling(z_free, z_in, z_chip);
}

std::complex<double> backing_image_factor(const TagBackingSpec& backing, double cos_psi, double frequency_hz) {
  if (backing.kind != TagBackingSpec::Kind::kGiven) return 1.0;
  if (!(cos_psi > 0.0)) return 0.0;  // behind the surface: the object blocks it
  // The tangential (TE) field's reflection: Γ = −1 for a perfect conductor.
  const std::complex<double> gamma = material_reflection(backing.material, frequency_hz, std::min(cos_psi, 1.0)).te;
  return 1.0 + gamma * std::polar(1.0, -2.0 * wavenumber_rad_m(frequency_hz) * backing.distance_m * cos_psi);
}

RadioMaterial backing_material(const std::string& name, const std::string& field) {
  if (auto m = builtin_material(name)) return *m;
  std::string known;
  for (const std::string& n : builtin_material_names()) known += (known.empty() ? "" : ", ") + n;
  throw field_error(field, "'" + clip(name) + "': unknown radio material (known: " + known +
                               "; or dielectric:EPS_R:SIGMA_S_M:DISTANCE_M)");
}

void validate(const TagAntennaSpec& antenna, const TagChipSpec& chip, const TagBackingSpec& backing,
              const std::string& field) {
  if (antenna.kind == TagAntennaSpec::Kind::kDipole) {
    if (!finite_positive(antenna.dipole.length_m))
      throw field_error(field + ".antenna.length_m", "must be a finite number > 0 (got " + num(antenna.dipole.length_m) + ")");
    if (!finite_positive(antenna.dipole.radius_m) || !(antenna.dipole.radius_m < 0.1 * antenna.dipole.length_m))
      throw field_error(field + ".antenna.radius_m", "must be > 0 and below a tenth of length_m (got " +
                                                         num(antenna.dipole.radius_m) + ")");
  } else if (antenna.kind == TagAntennaSpec::Kind::kTable) {
    if (antenna.table.empty()) throw field_error(field + ".antenna.table", "has no rows");
    for (size_t i = 0; i < antenna.table.size(); ++i) {
      const auto& p = antenna.table[i];
      if (!finite_positive(p.frequency_hz) || (i > 0 && !(p.frequency_hz > antenna.table[i - 1].frequency_hz)))
        throw field_error(field + ".antenna.table[" + std::to_string(i) + "]",
                          "frequencies must be finite, > 0 and increasing");
      if (!(std::isfinite(p.impedance_ohm.imag()) && finite_positive(p.impedance_ohm.real())))
        throw field_error(field + ".antenna.table[" + std::to_string(i) + "]",
                          "the resistance must be > 0 and the reactance finite");
    }
  }
  if (antenna.kind == TagAntennaSpec::Kind::kNone) {
    if (chip.kind != TagChipSpec::Kind::kMatched || chip.resistance_ohm != 0.0 || backing.kind == TagBackingSpec::Kind::kGiven)
      throw field_error(field + ".antenna", "a chip or a backing needs the tag's antenna (dipole or table)");
  }
  if (chip.kind != TagChipSpec::Kind::kMatched) {
    if (!finite_positive(chip.resistance_ohm))
      throw field_error(field + ".chip.resistance_ohm", "must be a finite number > 0 (got " + num(chip.resistance_ohm) + ")");
    if (!finite_positive(chip.capacitance_f) || chip.capacitance_f > 1e-6)
      throw field_error(field + ".chip.capacitance_f", "must be > 0 and at most 1e-6 F (got " + num(chip.capacitance_f) + ")");
  } else if (!(std::isfinite(chip.design_frequency_hz) && chip.design_frequency_hz >= 0.0 &&
               chip.design_frequency_hz <= 1e11)) {
    throw field_error(field + ".chip.design_frequency_hz", "must be ≥ 0 and at most 1e11 Hz (0: each carrier)");
  }
  if (backing.kind == TagBackingSpec::Kind::kGiven) {
    if (!(std::isfinite(backing.distance_m) && backing.distance_m > 0.0 && backing.distance_m <= 10.0))
      throw field_error(field + ".backing.distance_m", "must be > 0 and at most 10 m (got " + num(backing.distance_m) + ")");
    if (antenna.kind == TagAntennaSpec::Kind::kDipole && backing.distance_m < antenna.dipole.radius_m)
      throw field_error(field + ".backing.distance_m", "must be at least the wire's radius (" +
                                                         num(antenna.dipole.radius_m) + " m; got " +
                                                         num(backing.distance_m) + ")");
  }
}

}  // namespace rfidray
