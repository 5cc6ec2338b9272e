#pragma once
// The two reader models (switchable per antenna):
//  - paper:    eq. 4 phase (φ0 + 4πD/λ + n_φ + n_opt) mod 2π, eq. 5 RSSI round(40·log10(G_RT·λ/(4πD) + n_RSSI)),
//              read iff D ≤ r·|1 + n_r|, n_r ~ N(0, σ_r²). n_φ = noisephi·N(0,1), n_RSSI = noiserssi·N(0,1).
//              When G_RT·λ/(4πD) + n_RSSI ≤ 0 (noise larger than the signal) eq. 5 has no value: the reader
//              reports nothing, so that attempt is a no-read. (The seed Gazebo plugin reads `noiserssi` from
//              the `noisephi` SDF element; we do not copy that bug: each noise has its own parameter.)
//              Draw order: n_r, n_φ, n_opt, n_RSSI.
//  - physical: complex one-way channel h from a Channel (it already contains both antenna gains and the
//              polarization match); round trip h². Tag powered iff P_tx·|h|² ≥ chip sensitivity;
//              P_rx = P_tx·K·|h|⁴ (K = modulation_factor); read iff also P_rx ≥ reader sensitivity (noise-free
//              power); RSSI (dBm) = 10·log10(P_rx / 1 mW) + noise_rssi_db·N(0,1); phase φ0 − arg(h²) + n_φ + n_opt.
//              For the ideal channel h = √(G_R G_T)·λ/(4πD)·e^{−jkD}, φ0 − arg(h²) ≡ φ0 + 4πD/λ (eq. 3).
//              Draw order: n_φ, n_opt, n_RSSI.
// Both: every draw is made on every attempt (read or not), standard normals from one
// std::normal_distribution<double> per call, so the stream position after an attempt never depends on its
// outcome and runs are reproducible. Phase wrapped to [0, 2π) then rounded to the nearest of 2^phase_bits
// levels; RSSI rounded to the nearest multiple of rssi_resolution_db.
#include <complex>

#include "core/random.h"
#include "core/reader.h"

namespace rfidray {

// Everything a reader model needs to know about one read attempt.
struct LinkState {
  double distance_m = 0.0;             // true antenna–tag distance (paper model, CSV `dist`)
  double frequency_hz = 865.7e6;
  double phase_offset_rad = 0.0;       // φ0 of the current channel
  double pattern_phase_rad = 0.0;      // antenna and tag phase patterns along this link (round trip)
  size_t hop_index = 0;                // carrier index (read_probability)
  std::complex<double> h_one_way{0.0, 0.0};  // from the Channel (physical model)
  // The tag antenna's coupling at this carrier (core/tag_antenna.h, TagCoupling; physical model): the chip
  // receives P_tx·F·|h|², the reader P_tx·K·|h|⁴ and the phase turns by −backscatter_phase. Null: the point
  // tag (F = 1, K = reader.modulation_factor, no turn).
  const TagCoupling* tag_coupling = nullptr;
};

// Dispatches on reader.model. Draws from `rng` in a fixed order so runs are reproducible.
// Throws InputError for D ≤ 0, non-finite inputs, or a non-positive frequency.
Reading read_tag(const ReaderParams& reader, const TagParams& tag, const LinkState& link, Rng& rng);

Reading paper_reading(const ReaderParams& reader, const LinkState& link, Rng& rng);
Reading physical_reading(const ReaderParams& reader, const TagParams& tag, const LinkState& link, Rng& rng);

// The smallest |h|² (one-way channel power gain) at which the physical model can read the tag: the chip must
// be powered (P_tx·F·|h|² ≥ chip sensitivity) and the reader must decode (P_tx·K·|h|⁴ ≥ reader sensitivity);
// F = 1 and K = modulation_factor without a coupling.
double min_readable_h2(const ReaderParams& reader, const TagParams& tag, const TagCoupling* coupling = nullptr);

// Quantizes a phase in [0, 2π) to `bits` bits of 2π (0 bits: unchanged); result in [0, 2π).
double quantize_phase(double phase_rad, int bits);
// Rounds an RSSI to the nearest multiple of `resolution_db` (0: unchanged).
double quantize_rssi(double rssi_db, double resolution_db);

// Validates reader parameters (positive frequency, matching φ0 list, non-negative noise, ...).
// Throws InputError naming `field`.
void validate(const ReaderParams& reader, const std::string& field);
void validate(const TagParams& tag, const std::string& field);
void validate(const PhasePattern& pattern, const std::string& field);

}  // namespace rfidray
