#pragma once
// A tag as an antenna with an impedance and a chip, and what the surface it is stuck on does to it.
//
// Why: a tag's antenna is detuned by what it sits on. Its input impedance changes (a dipole 1 cm from metal:
// 76 + j14 Ω becomes ~2 − j2 Ω), so the chip, matched to the antenna in free space, receives a fraction of the
// power the antenna could deliver. The far-field effect of the surface (its image path) is a separate factor:
// the ray tracer finds it when the surface is meshed, TagMount adds it when it is not.
//
// The decomposition used (reciprocity; Nikitin & Rao, "Theory and measurement of backscattering from RFID
// tags", IEEE Antennas Propag. Mag. 48(6), 2006). With V_oc the open-circuit voltage of the antenna in place,
// V_oc = V_oc,free · AF (AF: direct + image wave; the current's shape along the wire barely changes), the
// power into the chip is
//     P_chip = |V_oc|² R_c / |Z_a + Z_c|² = P_free,matched · |AF|² · F,   F = 4 R_a0 R_c / |Z_a + Z_c|²
// where P_free,matched is what the channel's |h|² already gives (the antenna's free-space gain into a matched
// load), R_a0 = Re Z_a0 the free-space antenna resistance, Z_a the antenna's impedance in place, Z_c the chip's.
// F = τ · R_a0 / R_a with τ = 4 R_c R_a / |Z_a + Z_c|² the power transfer coefficient (available power of the
// antenna in place into the chip) and R_a0 / R_a the gain change of the antenna beside the surface.
// Backscatter (Nikitin & Rao, eq. 3): P_rx = P_tx · |h|⁴ · (R_a0/R_a)² · K, K = |ρ_1 − ρ_2|² / 4, with the power-
// wave reflection coefficients ρ_i = (Z_i − Z_a*) / (Z_i + Z_a) of the chip's two states (absorbing Z_c and
// modulating, a short by default). In free space with a matched chip K = 1/4, rfidray's default
// modulation_factor, and F = 1: a matched tag in free space reads exactly as without this model.
//
// Units: metres, hertz, ohms, farads. Thread-safe: value types and pure functions. Throws InputError naming
// the field (core/error.h) for bad parameters.
#include <complex>
#include <string>
#include <vector>

#include "core/material.h"
#include "core/thin_wire_dipole.h"

namespace rfidray {

// The tag's antenna. kNone: the paper's point tag (gain and pattern only, no impedance, no detuning).
struct TagAntennaSpec {
  enum class Kind { kNone, kDipole, kTable };
  Kind kind = Kind::kNone;
  ThinWireDipole dipole;  // kDipole: its wire (along the tag's local Z)
  // kTable: the free-space impedance against frequency (a datasheet's or a NEC run's), interpolated linearly
  // in frequency, held constant outside the table. A table antenna is not detuned by a backing (its geometry is
  // unknown): its free-space impedance and chip set F and K, and a backing adds only its image path.
  struct Point {
    double frequency_hz = 0.0;
    std::complex<double> impedance_ohm;
  };
  std::vector<Point> table;
  std::string table_source;  // file the table came from (messages)
};

// The chip. kMatched: the conjugate of the antenna's free-space impedance at design_frequency_hz (0: at each
// carrier, i.e. perfect match in free space); kSeries: R + 1/(jωC); kParallel: R ‖ C, the form chip datasheets
// give. The modulating state is a short (0 Ω), as in Nikitin & Rao's measurements.
struct TagChipSpec {
  enum class Kind { kMatched, kSeries, kParallel };
  Kind kind = Kind::kMatched;
  double resistance_ohm = 0.0;
  double capacitance_f = 0.0;
  double design_frequency_hz = 0.0;
};

// What the tag is stuck on. kNone: free space. kGiven: a surface `distance_m` behind the tag (its wire parallel
// to it; the surface's normal along the tag's local −X, the tag facing +X), not in the scene: the model adds its
// image path and blocks the half-space behind it. kScene: the nearest meshed facet within kSceneBackingSearch_m
// of the tag (when the channel has a scene), its material and distance; its image path is the ray tracer's.
// material: a perfect conductor (metal) is an image plane (core/thin_wire_dipole.h); any other radio material
// (core/material.h: the P.2040 ones, water, a user material) a dielectric half-space of its complex permittivity
// (core/dielectric_half_space.h). A slab (thickness_m > 0) is taken as the half-space of its material, an upper
// bound on its detuning.
struct TagBackingSpec {
  enum class Kind { kNone, kGiven, kScene };
  Kind kind = Kind::kNone;
  RadioMaterial material;
  double distance_m = 0.0;
  // kScene: the smaller in-plane size of the facet found (m). The detuning model assumes an infinite plane; a
  // facet narrower than the antenna (a shelf's front edge) detunes less, so the result is an upper bound there.
  double facet_extent_m = 1e300;
  bool faces_facet = true;  // kScene: false when the tag is beyond the facet's edge (not over its face)
};

// How far a scene backing looks for a surface. The detuning of a half-wave dipole beside metal falls to 0.1 dB at
// ~10 cm (NEC-2) and below 0.02 dB at λ/2; farther surfaces act through their paths only.
inline constexpr double kSceneBackingSearch_m = 0.15;

// The tag's electrical state at one frequency and mounting.
struct TagCoupling {
  std::complex<double> free_space_impedance_ohm;  // Z_a0
  std::complex<double> antenna_impedance_ohm;     // Z_a, in place
  std::complex<double> chip_impedance_ohm;        // Z_c
  double power_transfer = 1.0;      // τ = 4 R_c R_a / |Z_a + Z_c|²
  double chip_power_factor = 1.0;   // F = 4 R_a0 R_c / |Z_a + Z_c|²: multiplies |h|² for the chip's power
  double modulation_factor = 0.25;  // (R_a0/R_a)² · |ρ_1 − ρ_2|² / 4: multiplies |h|⁴ for the backscatter
  double backscatter_phase_rad = 0.0;  // arg(ρ_1 − ρ_2) in place minus in free space, (−π, π]
};

// Impedances. Throw InputError naming `field` for unusable parameters.
std::complex<double> antenna_free_space_impedance(const TagAntennaSpec& antenna, double frequency_hz,
                                                  const std::string& field = "tag.antenna");
// `material` null (or distance ≤ 0): free space.
std::complex<double> antenna_impedance_in_place(const TagAntennaSpec& antenna, const RadioMaterial* material,
                                                double distance_m, double frequency_hz,
                                                const std::string& field = "tag.backing");
std::complex<double> chip_impedance(const TagChipSpec& chip, const TagAntennaSpec& antenna, double frequency_hz,
                                    const std::string& field = "tag.chip");

// τ, F, K and the phase from the three impedances.
TagCoupling tag_coupling(std::complex<double> z_free_ohm, std::complex<double> z_in_place_ohm,
                         std::complex<double> z_chip_ohm);
// The same for a tag: antenna, chip and a surface (material, distance) behind it (material null or distance ≤ 0:
// free space).
TagCoupling tag_coupling(const TagAntennaSpec& antenna, const TagChipSpec& chip, const RadioMaterial* material,
                         double distance_m, double frequency_hz, const std::string& field = "tag");

// The image path of a kGiven backing, as a factor on the one-way channel: 1 + Γ(ψ)·e^{−j2kd·cosψ}, Γ the
// surface's Fresnel reflection coefficient for the field parallel to it (TE; −1 for metal), ψ the angle between
// the direction to the other end (tag frame) and the tag's +X; 0 behind the surface (cosψ ≤ 0: the object is
// taken as opaque: right for metal, roughly right for a box of water, which at 866 MHz costs ~29 dB/m (σ/2·η₀/√ε')
// plus ~4 dB at each face; wrong for a thin dielectric wall, which a tag behind it reads through). Exact for an
// infinite plane in the far field of the pair.
std::complex<double> backing_image_factor(const TagBackingSpec& backing, double cos_psi, double frequency_hz);

// The radio material a backing names: a built-in one (core/material.h). Throws InputError naming `field` and the
// known names.
RadioMaterial backing_material(const std::string& name, const std::string& field);

// Checks the three specs (finite, positive sizes). Throws InputError naming `field`.
void validate(const TagAntennaSpec& antenna, const TagChipSpec& chip, const TagBackingSpec& backing,
              const std::string& field);

}  // namespace rfidray
