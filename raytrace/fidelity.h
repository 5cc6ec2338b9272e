#pragma once
// `channel: auto` — model no more than the scene needs. On a sample of the scenario's own links
// (core/link_sample.h) every rung of a ladder of channel settings, cheapest first, is compared with the
// reference (full: double reflections and edge diffraction, exhaustive candidate search); the first rung whose
// errors on what a reader reports stay within the tolerance is picked:
//   ideal → los → los+blocked → [single-bounce with per-pose candidate rays] → single-bounce (exact search)
//   → double-bounce → full-selective → full → full exhaustive (the reference itself, always within).
// full-selective is a rung of its own, judged like the others: it is full's physics with diffraction skipped
// where UTD's transition function says it is small (raytrace/diffraction.cpp), so whether that is within the
// tolerance depends on the scene, and only the comparison with full on the scene's own links can say.
// The candidate-ray rung uses the user's candidate_rays when set, else 4096 rays when the scenario has at least
// 1000 tags per antenna pose (below that the per-pose rays cost more than they save, bench/bench_sweep).
// The ladder's order is its cost order as measured by bench/bench_sweep (README, "Speed and accuracy").
// A rung is within tolerance when the 95th percentile of the round-trip phase error and of the RSSI error
// (core/channel_error.h: links readable in either channel; a link readable in only one counts as infinite
// error) are ≤ the tolerance. Deterministic: no timing is involved in the choice; rays per link (Embree calls
// counted on the sample) are reported for information.
#include <memory>
#include <string>
#include <vector>

#include "core/channel.h"
#include "core/channel_error.h"
#include "core/link_sample.h"
#include "raytrace/scene.h"
#include "raytrace/trace_options.h"

namespace rfidray {

struct FidelityRung {
  std::string label;     // "ideal", "los", "los+blocked", "single-bounce rays=4096", "single-bounce", ..., "full"
  ChannelLevel level;    // kIdeal: the free-space channel (options unused); else options.level
  TraceOptions options;
};

struct FidelityTolerance {
  double phase_rad = 0.05;
  double rssi_db = 0.5;
};

struct FidelityRow {
  FidelityRung rung;
  ChannelErrorStats errors;
  double rays_per_link = 0.0;  // Embree rays per sampled link, per-pose candidate rays included
  bool within = false;
};

struct FidelityChoice {
  FidelityRung picked;
  std::vector<FidelityRow> rows;  // the rungs evaluated, in ladder order (evaluation stops at the pick)
  size_t links = 0;               // sampled links
  std::string reason;             // one line for the user
  // Sampled links where the reference rung is itself outside its validity near a metal edge (core/level_validity.h).
  size_t links_outside_validity = 0;
};

// The ladder for user settings `base` (drop threshold, epsilons, max path length and candidate rays are
// kept; level and candidate mode vary) and the mean number of tags per antenna pose. The last rung is the
// reference.
std::vector<FidelityRung> fidelity_ladder(const TraceOptions& base, double tags_per_pose = 0.0);

// Evaluates the ladder on `batches` and picks. Throws InputError when the sample is empty.
FidelityChoice choose_fidelity(std::shared_ptr<const Scene> scene, const std::vector<LinkBatch>& batches,
                               const TraceOptions& base, const FidelityTolerance& tolerance);

// The channel of a rung.
std::unique_ptr<Channel> make_rung_channel(std::shared_ptr<const Scene> scene, const FidelityRung& rung);

// The choice as a small table (one line per evaluated rung), for `rfidray simulate` to print.
std::vector<std::string> describe(const FidelityChoice& choice);

}  // namespace rfidray
