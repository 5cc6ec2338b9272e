#include "core/read_probability.h"

#include <cmath>
#include <limits>
#include <numbers>

#include "core/error.h"

#include "core/units.h"

namespace rfidray {

double standard_normal_cdf(double x) { return 0.5 * std::erfc(-x / std::numbers::sqrt2); }

namespace {

// P(X > t) for X ~ N(mean, sigma²); a step when sigma = 0 (X = mean: P(mean > t)).
double above(double mean, double sigma, double t) {
  if (!(sigma > 0.0)) return mean > t ? 1.0 : 0.0;
  return standard_normal_cdf((mean - t) / sigma);
}

double report_probability(const ReaderParams& reader, const LinkState& link) {
  if (reader.read_probability.empty()) return 1.0;
  return reader.read_probability.size() == 1 ? reader.read_probability[0] : reader.read_probability.at(link.hop_index);
}

}  // namespace

double read_probability(const ReaderParams& reader, const TagParams& tag, const LinkState& link) {
  if (!(std::isfinite(link.distance_m) && link.distance_m > 0.0))
    throw InputError("read probability of antenna '" + reader.name + "': distance must be finite and > 0");
  if (!(std::isfinite(link.frequency_hz) && link.frequency_hz > 0.0))
    throw InputError("read probability of antenna '" + reader.name + "': frequency must be finite and > 0");
  const double report = report_probability(reader, link);
  if (reader.model == ReaderModelKind::kPhysical) {
    // The same decision as physical_reading(): noise-free powers against both thresholds.
    const double p_tx_w = dbm_to_watt(reader.tx_power_dbm);
    const double gain2 = std::norm(link.h_one_way);
    const TagCoupling* c = link.tag_coupling;
    const double chip_factor = c ? c->chip_power_factor : 1.0;
    const double k_mod = c ? c->modulation_factor : reader.modulation_factor;
    if (!(p_tx_w * chip_factor * gain2 >= dbm_to_watt(tag.chip_sensitivity_dbm))) return 0.0;
    const double p_rx_w = p_tx_w * k_mod * gain2 * gain2;
    if (!(p_rx_w >= dbm_to_watt(reader.sensitivity_dbm))) return 0.0;
    return report;
  }
  // Paper model: D ≤ r·|1 + n_r|  ⇔  1 + n_r ≥ a  or  1 + n_r ≤ −a  (a = D/r > 0).
  const double a = link.distance_m / reader.range_m;
  const double sr = reader.range_sigma;
  double p_range = 0.0;
  if (sr > 0.0) {
    p_range = above(1.0, sr, a) + standard_normal_cdf((-a - 1.0) / sr);
  } else {
    p_range = a <= 1.0 ? 1.0 : 0.0;
  }
  const double amplitude = reader.communication_gain * wavelength_m(link.frequency_hz) / (4.0 * kPi * link.distance_m);
  const double p_amplitude = above(amplitude, reader.noise_rssi, 0.0);
  return std::min(1.0, p_range) * p_amplitude * report;
}

}  // namespace rfidray
