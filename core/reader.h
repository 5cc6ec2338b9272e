#pragma once
// Reader antenna and tag parameters, and the reading a reader reports. Field names follow the seed
// plugin's SDF parameters where they exist (frequency, noisephi, noiserssi, range, optional_distribution,
// optional_distribution_params, communication_gain, update_rate) so its users can copy them.
#include <complex>
#include <string>
#include <vector>

#include "core/antenna_pattern.h"
#include "core/geometry.h"
#include "core/phase_pattern.h"
#include "core/polarization.h"
#include "core/tag_antenna.h"

namespace rfidray {

enum class ReaderModelKind { kPaper, kPhysical };

// The eight optional noise distributions of the seed plugin (paper eq. 4, n_optional), as in <random>.
enum class DistributionKind { kNone, kUniform, kExponential, kGamma, kWeibull, kNormal, kLognormal, kChiSquared, kCauchy };

struct OptionalDistribution {
  DistributionKind kind = DistributionKind::kNone;
  std::vector<double> params;
};

struct ReaderParams {
  std::string name;
  std::vector<double> frequencies_hz{865.7e6};  // one entry: fixed; several: hopping in this order
  std::vector<double> phase_offsets_rad{0.0};     // φ0 per channel (same length as frequencies_hz)
  double hop_dwell_s = 0.4;                       // time on one channel before hopping (EU readers: ~0.4 s)
  double tx_power_dbm = 30.0;
  double noise_phi_rad = 0.1;       // σ of n_φ (paper eq. 4)
  double noise_rssi = 0.01;         // σ of n_RSSI (paper eq. 5)
  double noise_rssi_db = 0.5;       // σ (dB) of the RSSI noise added in dB by the physical model
  double range_m = 7.0;             // r of the read condition D ≤ r·|1 + n_r| (paper model)
  double range_sigma = 0.05;        // σ_r of n_r (paper §III-A, after DiGiampaolo & Martinelli)
  OptionalDistribution optional_distribution;
  double communication_gain = 1.0;  // G_RT of eq. 5 (linear)
  double update_rate_hz = 15.0;
  int phase_bits = 12;              // phase quantization: 2π / 2^bits per step (0: none)
  double rssi_resolution_db = 1.0;  // RSSI reported in steps of this size (paper: integer dB)
  double sensitivity_dbm = -80.0;   // reader receive sensitivity (physical model)
  double modulation_factor = 0.25;  // K of the backscatter link (physical model): fraction re-radiated
  ReaderModelKind model = ReaderModelKind::kPaper;
  AntennaPattern pattern;           // physical model / ray-traced channels
  Polarization polarization;

  // Hardware effects of real readers (README, "Simulating a real reader"). Defaults: off.
  // Where the waves really start, in the antenna frame (boresight +X): the channel and the distance are
  // computed from pose ∘ offset, while the reads report the mounting pose, as a real reader does.
  Vec3 phase_centre_offset_m = Vec3::Zero();
  PhasePattern phase_pattern;       // round-trip phase vs direction of the tag (core/phase_pattern.h)
  // Physical model: the signal-to-noise ratio (dB) at exactly sensitivity_dbm; > 0 adds the receiver's
  // noise, which grows as the signal nears sensitivity: SNR = SNR_s·P_rx/P_s, phase variance += 1/(2·SNR)
  // rad² and RSSI σ² += (8.686/√(2·SNR))² dB² (a tone in complex white noise; Kay, Fundamentals of Statistical
  // Signal Processing I, 1993, §3.11). 0: off.
  double snr_at_sensitivity_db = 0.0;
  // Probability that an attempt that could be read is reported, per carrier (index-aligned with frequencies_hz,
  // or one value for all): real readers read some channels more often than others. Empty: always.
  std::vector<double> read_probability;
};

struct TagParams {
  std::string name;  // EPC or a user name
  double gain_dbi = 2.15;            // half-wave dipole-like tag
  double chip_sensitivity_dbm = -20.0;
  AntennaPattern pattern;            // used by the physical model and ray-traced channels
  Polarization polarization;
  PhasePattern phase_pattern;        // round-trip phase vs direction of the antenna, in the tag frame
  // The tag as an antenna with an impedance, its chip and what it is stuck on (core/tag_antenna.h; physical
  // model). Default: the paper's point tag, no detuning (reads exactly as before the model existed).
  TagAntennaSpec antenna;
  TagChipSpec chip;
  TagBackingSpec backing;
};

// What one read attempt yields. `read == false` means the tag did not answer; phase/RSSI are then unset.
struct Reading {
  bool read = false;
  double phase_rad = 0.0;  // [0, 2π)
  double rssi_dbm = 0.0;
};

}  // namespace rfidray
