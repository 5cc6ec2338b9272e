#include "core/reader_model.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include "core/distribution.h"
#include "core/error.h"
#include "core/limits.h"
#include "core/number_text.h"
#include "core/units.h"

namespace rfidray {
namespace {

std::string link_field(const ReaderParams& reader, const char* what) {
  return (reader.name.empty() ? std::string("link") : "antenna '" + reader.name + "' link") + "." + what;
}

void check_link(const ReaderParams& reader, const LinkState& link) {
  if (!(std::isfinite(link.distance_m) && link.distance_m > 0.0))
    throw field_error(link_field(reader, "distance_m"),
                      "antenna–tag distance must be finite and > 0 (got " + num(link.distance_m) + ")");
  if (!(std::isfinite(link.frequency_hz) && link.frequency_hz > 0.0))
    throw field_error(link_field(reader, "frequency_hz"), "must be finite and > 0 (got " + num(link.frequency_hz) + ")");
  if (!std::isfinite(link.phase_offset_rad))
    throw field_error(link_field(reader, "phase_offset_rad"), "must be finite (got " + num(link.phase_offset_rad) + ")");
}

void require_finite(double v, const std::string& field) {
  if (!std::isfinite(v)) throw field_error(field, "must be a finite number (got " + num(v) + ")");
}
void require_positive(double v, const std::string& field) {
  if (!(std::isfinite(v) && v > 0.0)) throw field_error(field, "must be finite and > 0 (got " + num(v) + ")");
}
void require_non_negative(double v, const std::string& field) {
  if (!(std::isfinite(v) && v >= 0.0)) throw field_error(field, "must be finite and >= 0 (got " + num(v) + ")");
}

void validate_polarization(const Polarization& p, const std::string& field) {
  if (!p.axis_local.allFinite() || !std::isfinite(p.axis_local.norm()) || p.axis_local.norm() < 1e-12)
    throw field_error(field + ".axis", "must be a finite, non-zero vector");
}

// The draw of read_probability: made on every attempt when the reader has one (after the model's own draws),
// so the stream position never depends on the outcome; returns whether the attempt may be reported.
bool drawn_reported(const ReaderParams& reader, const LinkState& link, Rng& rng) {
  if (reader.read_probability.empty()) return true;
  const double p = reader.read_probability.size() == 1 ? reader.read_probability[0]
                                                       : reader.read_probability.at(link.hop_index);
  return std::uniform_real_distribution<double>(0.0, 1.0)(rng) < p;
}

}  // namespace

double quantize_phase(double phase_rad, int bits) {
  const double wrapped = wrap_to_2pi(phase_rad);
  if (bits <= 0) return wrapped;
  // Round to the nearest of 2^bits levels; the level 2^bits is the same angle as 0.
  const double levels = std::ldexp(1.0, bits);
  const double step = kTwoPi / levels;
  double k = std::round(wrapped / step);
  if (k >= levels) k = 0.0;
  return k * step;
}

double quantize_rssi(double rssi_db, double resolution_db) {
  if (!(resolution_db > 0.0)) return rssi_db;
  return std::round(rssi_db / resolution_db) * resolution_db;
}

// Draw order (fixed, all four always drawn so that the stream position after a read attempt does not
// depend on its outcome): 1. n_r, 2. n_φ, 3. n_opt, 4. n_RSSI. Standard normals come from one
// std::normal_distribution<double> per call, in that order.
// Note: the seed Gazebo plugin reads `noiserssi` from the `noisephi` SDF element, so its RSSI noise is
// the phase noise; we read each from its own parameter (ReaderParams::noise_rssi).
Reading paper_reading(const ReaderParams& reader, const LinkState& link, Rng& rng) {
  check_link(reader, link);
  std::normal_distribution<double> unit(0.0, 1.0);
  const double n_r = reader.range_sigma * unit(rng);
  const double n_phi = reader.noise_phi_rad * unit(rng);
  const double n_opt = sample(reader.optional_distribution, rng);
  const double n_rssi = reader.noise_rssi * unit(rng);
  const bool reported = drawn_reported(reader, link, rng);

  const double lambda = wavelength_m(link.frequency_hz);
  const double d = link.distance_m;
  Reading r;
  // Perturbed range r̃ = r·|1 + n_r| (paper §IV, after DiGiampaolo & Martinelli).
  if (d > reader.range_m * std::abs(1.0 + n_r)) return r;
  // Eq. 5: RSSI = round(40·log10(G_RT·λ/(4πD) + n_RSSI)). The noise is added to the linear amplitude, so
  // it can drive the argument to ≤ 0; a real reader then reports nothing, so that attempt is no read.
  const double amplitude = reader.communication_gain * lambda / (4.0 * kPi * d) + n_rssi;
  if (!(amplitude > 0.0) || !reported) return r;
  // Eq. 4: φ = (φ0 + 4πD/λ + n_φ + n_opt) mod 2π, then quantized (+ the phase patterns, 0 by default).
  const double phase = link.phase_offset_rad + 4.0 * kPi * d / lambda + n_phi + n_opt + link.pattern_phase_rad;
  if (!std::isfinite(phase)) return r;  // e.g. a Cauchy draw overflowing: no usable phase
  r.read = true;
  r.phase_rad = quantize_phase(phase, reader.phase_bits);
  r.rssi_dbm = quantize_rssi(40.0 * std::log10(amplitude), reader.rssi_resolution_db);
  return r;
}

// Draw order (fixed, all three always drawn): 1. n_φ, 2. n_opt, 3. n_RSSI (dB).
Reading physical_reading(const ReaderParams& reader, const TagParams& tag, const LinkState& link, Rng& rng) {
  check_link(reader, link);
  if (!(std::isfinite(link.h_one_way.real()) && std::isfinite(link.h_one_way.imag())))
    // Inputs are range-checked where they enter, so this is a bug, not bad input (exit 1, not 2).
    throw std::logic_error("internal error: the channel of antenna '" + reader.name + "' gave a non-finite h (" +
                           num(link.h_one_way.real()) + ", " + num(link.h_one_way.imag()) + ") at " +
                           num(link.frequency_hz) + " Hz, distance " + num(link.distance_m) + " m");
  std::normal_distribution<double> unit(0.0, 1.0);
  const double z_phi = unit(rng);
  const double n_opt = sample(reader.optional_distribution, rng);
  const double z_rssi = unit(rng);
  const bool reported = drawn_reported(reader, link, rng);

  Reading r;
  const double p_tx_w = dbm_to_watt(reader.tx_power_dbm);
  const double gain2 = std::norm(link.h_one_way);  // |h|², includes both antenna gains and polarization
  const TagCoupling* c = link.tag_coupling;
  // Forward link: the tag chip wakes up iff the power it receives reaches its sensitivity (F: the chip's share
  // of what a matched antenna in free space would deliver, core/tag_antenna.h).
  const double chip_factor = c ? c->chip_power_factor : 1.0;
  if (!(p_tx_w * chip_factor * gain2 >= dbm_to_watt(tag.chip_sensitivity_dbm))) return r;
  // Reverse link: backscattered power P_rx = P_tx·K·|h|⁴ (monostatic, round trip h²).
  const double k_mod = c ? c->modulation_factor : reader.modulation_factor;
  const double p_rx_w = p_tx_w * k_mod * gain2 * gain2;
  if (!(p_rx_w >= dbm_to_watt(reader.sensitivity_dbm)) || !reported) return r;  // noise-free power decides
  double sigma_phi = reader.noise_phi_rad, sigma_rssi_db = reader.noise_rssi_db;
  if (reader.snr_at_sensitivity_db > 0.0) {
    // Receiver noise: SNR = SNR_s·P_rx/P_s; a tone in complex white noise has phase variance 1/(2·SNR) and
    // relative amplitude variance 1/(2·SNR), i.e. 8.686/√(2·SNR) dB of power.
    const double snr = std::pow(10.0, reader.snr_at_sensitivity_db / 10.0) * p_rx_w / dbm_to_watt(reader.sensitivity_dbm);
    sigma_phi = std::sqrt(sigma_phi * sigma_phi + 0.5 / snr);
    const double rssi_term = 8.685889638 / std::sqrt(2.0 * snr);
    sigma_rssi_db = std::sqrt(sigma_rssi_db * sigma_rssi_db + rssi_term * rssi_term);
  }
  const double n_phi = sigma_phi * z_phi;
  const double n_rssi_db = sigma_rssi_db * z_rssi;
  const std::complex<double> h2 = link.h_one_way * link.h_one_way;
  // Round-trip phase φ0 − arg(h²): for the ideal channel this is φ0 + 4πD/λ (eq. 3); + the phase patterns.
  // The tag's modulation turns the backscatter by arg(ρ_1 − ρ_2) relative to free space (core/tag_antenna.h).
  const double tag_turn = c ? c->backscatter_phase_rad : 0.0;
  const double phase = link.phase_offset_rad - std::arg(h2) - tag_turn + n_phi + n_opt + link.pattern_phase_rad;
  if (!std::isfinite(phase)) return r;
  r.read = true;
  r.phase_rad = quantize_phase(phase, reader.phase_bits);
  r.rssi_dbm = quantize_rssi(watt_to_dbm(p_rx_w) + n_rssi_db, reader.rssi_resolution_db);
  return r;
}

double min_readable_h2(const ReaderParams& reader, const TagParams& tag, const TagCoupling* coupling) {
  const double p_tx_w = dbm_to_watt(reader.tx_power_dbm);
  const double chip_factor = coupling ? coupling->chip_power_factor : 1.0;
  const double k_mod = coupling ? coupling->modulation_factor : reader.modulation_factor;
  return std::max(dbm_to_watt(tag.chip_sensitivity_dbm) / (p_tx_w * chip_factor),
                  std::sqrt(dbm_to_watt(reader.sensitivity_dbm) / (p_tx_w * k_mod)));
}

Reading read_tag(const ReaderParams& reader, const TagParams& tag, const LinkState& link, Rng& rng) {
  switch (reader.model) {
    case ReaderModelKind::kPaper: return paper_reading(reader, link, rng);
    case ReaderModelKind::kPhysical: return physical_reading(reader, tag, link, rng);
  }
  return paper_reading(reader, link, rng);
}

void validate(const ReaderParams& reader, const std::string& field) {
  if (reader.frequencies_hz.empty()) throw field_error(field + ".frequency", "needs at least one frequency");
  for (size_t i = 0; i < reader.frequencies_hz.size(); ++i)
    limits::check_range(reader.frequencies_hz[i], limits::kMinFrequencyHz, limits::kMaxFrequencyHz,
                        field + ".frequency[" + std::to_string(i) + "]", "Hz");
  if (reader.phase_offsets_rad.size() != reader.frequencies_hz.size())
    throw field_error(field + ".phase_offset", "needs one φ0 per frequency (" +
                                                   std::to_string(reader.frequencies_hz.size()) + " frequencies, " +
                                                   std::to_string(reader.phase_offsets_rad.size()) + " offsets)");
  for (size_t i = 0; i < reader.phase_offsets_rad.size(); ++i)
    require_finite(reader.phase_offsets_rad[i], field + ".phase_offset[" + std::to_string(i) + "]");
  require_positive(reader.hop_dwell_s, field + ".hop_dwell_s");
  limits::check_range(reader.tx_power_dbm, -limits::kMaxPowerDbm, limits::kMaxPowerDbm, field + ".tx_power_dbm", "dBm");
  limits::check_range(reader.noise_phi_rad, 0.0, limits::kMaxNoisePhaseRad, field + ".noisephi", "rad");
  limits::check_range(reader.noise_rssi, 0.0, limits::kMaxNoiseRssiLinear, field + ".noiserssi", "(σ of n_RSSI)");
  limits::check_range(reader.noise_rssi_db, 0.0, limits::kMaxNoiseRssiDb, field + ".noise_rssi_db", "dB");
  require_positive(reader.range_m, field + ".range");
  require_non_negative(reader.range_sigma, field + ".range_sigma");
  // Re-parse so that a hand-built OptionalDistribution gets the same checks as a parsed one.
  parse_distribution(reader.optional_distribution.kind == DistributionKind::kNone
                         ? std::string()
                         : to_string(reader.optional_distribution.kind),
                     reader.optional_distribution.params, field + ".optional_distribution");
  require_positive(reader.communication_gain, field + ".communication_gain");
  limits::check_range(reader.communication_gain, 0.0, 1e10, field + ".communication_gain", "(linear)");
  require_positive(reader.update_rate_hz, field + ".update_rate");
  if (reader.phase_bits < 0 || reader.phase_bits > 32)
    throw field_error(field + ".phase_bits", "must be in [0, 32] (got " + std::to_string(reader.phase_bits) + ")");
  limits::check_range(reader.rssi_resolution_db, 0.0, 100.0, field + ".rssi_resolution_db", "dB");
  limits::check_range(reader.sensitivity_dbm, -limits::kMaxPowerDbm, limits::kMaxPowerDbm, field + ".sensitivity_dbm", "dBm");
  if (!(std::isfinite(reader.modulation_factor) && reader.modulation_factor > 0.0 && reader.modulation_factor <= 1.0))
    throw field_error(field + ".modulation_factor", "must be in (0, 1] (got " + num(reader.modulation_factor) + ")");
  reader.pattern.validate(field + ".pattern");
  validate_polarization(reader.polarization, field + ".polarization");
  for (int k = 0; k < 3; ++k) require_finite(reader.phase_centre_offset_m[k], field + ".phase_centre_offset_m");
  if (reader.phase_centre_offset_m.norm() > 10.0)
    throw field_error(field + ".phase_centre_offset_m", "must be within 10 m of the antenna (got " +
                                                            num(reader.phase_centre_offset_m.norm()) + " m)");
  validate(reader.phase_pattern, field + ".phase_pattern");
  limits::check_range(reader.snr_at_sensitivity_db, 0.0, 100.0, field + ".snr_at_sensitivity_db", "dB");
  if (!reader.read_probability.empty() && reader.read_probability.size() != 1 &&
      reader.read_probability.size() != reader.frequencies_hz.size())
    throw field_error(field + ".read_probability", "needs one value or one per frequency (" +
                                                       std::to_string(reader.frequencies_hz.size()) + ")");
  for (double p : reader.read_probability)
    if (!(p >= 0.0 && p <= 1.0)) throw field_error(field + ".read_probability", "must be in [0, 1] (got " + num(p) + ")");
}

void validate(const PhasePattern& pattern, const std::string& field) {
  for (double a : pattern.azimuth_rad) require_finite(a, field + ".azimuth_rad");
  for (double e : pattern.elevation_rad) require_finite(e, field + ".elevation_rad");
  if (pattern.azimuth_rad.size() > 8 || pattern.elevation_rad.size() > 8)
    throw field_error(field, "at most 8 coefficients per angle");
  for (double c : pattern.ripple_cos_rad) require_finite(c, field + ".ripple");
  for (double c : pattern.ripple_sin_rad) require_finite(c, field + ".ripple");
  if (pattern.ripple_cos_rad.size() != pattern.ripple_sin_rad.size() || pattern.ripple_cos_rad.size() > 180)
    throw field_error(field, "ripple: at most 180 harmonics, as many cosine as sine terms");
}

void validate(const TagParams& tag, const std::string& field) {
  limits::check_range(tag.gain_dbi, -limits::kMaxGainDbi, limits::kMaxGainDbi, field + ".gain_dbi", "dBi");
  limits::check_range(tag.chip_sensitivity_dbm, -limits::kMaxPowerDbm, limits::kMaxPowerDbm,
                      field + ".chip_sensitivity_dbm", "dBm");
  tag.pattern.validate(field + ".pattern");
  validate_polarization(tag.polarization, field + ".polarization");
  validate(tag.phase_pattern, field + ".phase_pattern");
  validate(tag.antenna, tag.chip, tag.backing, field);
}

}  // namespace rfidray
