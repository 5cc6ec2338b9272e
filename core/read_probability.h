#pragma once
// The probability that one read attempt succeeds, in closed form, for the two reader models of
// core/reader_model.h — what read_tag() returns as `read` averaged over its random draws. Used to map coverage
// (planning/coverage_map.h) without Monte Carlo, so a map is deterministic and needs no seed.
//
//  - paper:    read iff D ≤ r·|1 + n_r| (n_r ~ N(0, σ_r²)) and G_RT·λ/(4πD) + n_RSSI > 0 (n_RSSI ~ N(0, σ²)),
//              independent draws, so  P = P(|1 + n_r| ≥ D/r) · P(n_RSSI > −A)
//                 = [Q((a − 1)/σ_r) + Φ((−a − 1)/σ_r)] · Φ(A/σ),  a = D/r, A = G_RT·λ/(4πD);
//  - physical: read iff the noise-free powers pass both thresholds (no draw decides it): P ∈ {0, 1};
//  - both:     times the reader's read_probability of the carrier (the report draw).
// The optional phase distribution changes no read except by overflowing the phase (a Cauchy draw of ~1e308),
// which is ignored here. Thread-safe (pure). Throws InputError on the inputs read_tag() rejects.
#include "core/reader.h"
#include "core/reader_model.h"

namespace rfidray {

double read_probability(const ReaderParams& reader, const TagParams& tag, const LinkState& link);

// Standard normal CDF Φ(x) = erfc(−x/√2)/2.
double standard_normal_cdf(double x);

}  // namespace rfidray
