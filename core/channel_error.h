#pragma once
// How far one channel's values are from a reference's, on the quantities a reader reports: the round-trip
// phase arg(h²) and the RSSI ∝ |h|⁴ (paper eq. 1), over the links that can be read at all. Used by
// `channel: auto` (raytrace/fidelity.h) and the accuracy benchmarks.
#include <complex>
#include <span>
#include <string>

namespace rfidray {

struct ChannelErrorStats {
  size_t links = 0;               // links readable in the reference or in the test (the ones compared)
  size_t status_mismatches = 0;   // of those, readable in one and not in the other (counted as infinite error)
  // |wrap(arg h_test² − arg h_ref²)|, rad
  double phase_p50_rad = 0.0, phase_p95_rad = 0.0, phase_max_rad = 0.0;
  // |40·log10(|h_test| / |h_ref|)|, dB (RSSI ∝ |h|⁴)
  double rssi_p50_db = 0.0, rssi_p95_db = 0.0, rssi_max_db = 0.0;
  // ||h_test| / |h_ref| − 1|
  double magnitude_p50 = 0.0, magnitude_p95 = 0.0;
  // The same p95s over the links readable in both (status mismatches left out), for charts.
  double phase_p95_both_rad = 0.0, rssi_p95_both_db = 0.0;
};

// `min_readable_h2[i]`: the |h|² below which link i cannot be read (min_readable_h2 in core/reader_model.h).
// Links readable in neither channel do not count: their values never reach a reading. Percentiles are
// nearest-rank. All spans have the same length.
ChannelErrorStats channel_errors(std::span<const std::complex<double>> reference,
                                 std::span<const std::complex<double>> test,
                                 std::span<const double> min_readable_h2);

// One of the errors above as text for a table or a CSV: `value` to `significant_digits` (printf %.*g), or
// `not_finite` when it is not a finite number — a percentile that links readable in only one channel reach (+∞),
// or a value that was not computed (NaN). No output prints "inf" or "nan": a table says why, a CSV leaves the
// field empty (its header's README says so). Thread-safe; throws only std::bad_alloc.
std::string error_text(double value, int significant_digits, const std::string& not_finite);

}  // namespace rfidray
