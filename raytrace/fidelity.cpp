#include "raytrace/fidelity.h"

#include "core/level_validity.h"

#include <omp.h>

#include <cstdio>
#include <exception>

#include "core/error.h"
#include "core/level_validity.h"
#include "raytrace/path_finder.h"
#include "raytrace/raytraced_channel.h"

namespace rfidray {
namespace {

// One rung's one-way channels on every sampled link (batch order), and the rays it took.
struct RungValues {
  std::vector<std::complex<double>> h;
  uint64_t rays = 0;                // traced for the sampled links
  double pose_rays_per_link = 0.0;  // per-pose candidate rays, shared out over the present tags (summed)
};

RungValues evaluate(const std::shared_ptr<const Scene>& scene, const FidelityRung& rung,
                    const std::vector<LinkBatch>& batches) {
  RungValues v;
  v.h.reserve(link_count(batches));
  if (rung.level == ChannelLevel::kIdeal) {
    const IdealChannel ideal;
    for (const LinkBatch& b : batches) {
      std::vector<std::complex<double>> h(b.tag_ends.size());
      ideal.one_way(b.antenna_end, b.tag_ends, b.frequency_hz, h);
      v.h.insert(v.h.end(), h.begin(), h.end());
    }
    return v;
  }
  const PathFinder finder(scene, rung.options);
  PoseCandidates candidates;
  for (const LinkBatch& b : batches) {
    finder.prepare_pose(b.antenna_end.pose.position, candidates);
    // The pose's candidate rays serve all its present tags, not only the sampled ones.
    if (!candidates.all)
      v.pose_rays_per_link += static_cast<double>(rung.options.candidate_rays) /
                              static_cast<double>(std::max<size_t>(1, b.tags_present)) *
                              static_cast<double>(b.tag_ends.size());
    const size_t first = v.h.size();
    v.h.resize(first + b.tag_ends.size());
    const auto n = static_cast<std::ptrdiff_t>(b.tag_ends.size());
    uint64_t rays = 0;
    std::exception_ptr error;
    // Rays are counted per thread (tl_rays_traced) and summed: the total does not depend on the schedule.
#pragma omp parallel reduction(+ : rays) if (n >= 64)
    {
      const uint64_t before = tl_rays_traced;
      std::vector<TracedPath> paths;
#pragma omp for schedule(dynamic, 16)
      for (std::ptrdiff_t i = 0; i < n; ++i) {
        try {
          finder.trace(b.antenna_end, b.tag_ends[i], b.frequency_hz, candidates, paths);
          std::complex<double> sum{0.0, 0.0};
          for (const TracedPath& p : paths) sum += p.contribution;
          v.h[first + i] = sum;
        } catch (...) {
#pragma omp critical(rfidray_fidelity_error)
          if (!error) error = std::current_exception();
        }
      }
      rays += tl_rays_traced - before;
    }
    if (error) std::rethrow_exception(error);
    v.rays += rays;
  }
  return v;
}

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

}  // namespace

std::vector<FidelityRung> fidelity_ladder(const TraceOptions& base, double tags_per_pose) {
  std::vector<FidelityRung> ladder;
  ladder.push_back({to_string(ChannelLevel::kIdeal), ChannelLevel::kIdeal, base});
  auto rung = [&](ChannelLevel level, CandidateMode mode, int rays, const std::string& suffix) {
    TraceOptions o = base;
    o.level = level;
    o.candidates = mode;
    o.candidate_rays = rays;
    ladder.push_back({to_string(level) + suffix, level, o});
  };
  rung(ChannelLevel::kLos, CandidateMode::kExact, 0, "");
  rung(ChannelLevel::kLosBlocked, CandidateMode::kExact, 0, "");
  const int rays = base.candidate_rays > 0 ? base.candidate_rays : tags_per_pose >= 1000.0 ? 4096 : 0;
  if (rays > 0) rung(ChannelLevel::kSingleBounce, CandidateMode::kExact, rays, " rays=" + std::to_string(rays));
  rung(ChannelLevel::kSingleBounce, CandidateMode::kExact, 0, "");
  rung(ChannelLevel::kDoubleBounce, CandidateMode::kExact, 0, "");
  rung(ChannelLevel::kFullSelective, CandidateMode::kExact, 0, "");
  rung(ChannelLevel::kFull, CandidateMode::kExact, 0, "");
  rung(ChannelLevel::kFull, CandidateMode::kExhaustive, 0, " exhaustive");
  return ladder;
}

FidelityChoice choose_fidelity(std::shared_ptr<const Scene> scene, const std::vector<LinkBatch>& batches,
                               const TraceOptions& base, const FidelityTolerance& tolerance) {
  if (!(tolerance.phase_rad >= 0.0) || !(tolerance.rssi_db >= 0.0))
    throw InputError("channel auto: tolerances must be >= 0");
  FidelityChoice choice;
  choice.links = link_count(batches);
  if (choice.links == 0) throw InputError("channel auto: the scenario has no antenna–tag link to sample");
  std::vector<double> min_h2;
  for (const LinkBatch& b : batches) min_h2.insert(min_h2.end(), b.min_readable_h2.begin(), b.min_readable_h2.end());
  double present = 0.0;
  for (const LinkBatch& b : batches) present += static_cast<double>(b.tags_present);
  const std::vector<FidelityRung> ladder = fidelity_ladder(base, present / static_cast<double>(batches.size()));
  const RungValues reference = evaluate(scene, ladder.back(), batches);
  for (size_t i = 0; i < ladder.size(); ++i) {
    const bool is_reference = i + 1 == ladder.size();
    const RungValues values = is_reference ? reference : evaluate(scene, ladder[i], batches);
    FidelityRow row;
    row.rung = ladder[i];
    row.errors = channel_errors(reference.h, values.h, min_h2);
    row.rays_per_link = (static_cast<double>(values.rays) + values.pose_rays_per_link) / static_cast<double>(choice.links);
    row.within = is_reference ||
                 (row.errors.phase_p95_rad <= tolerance.phase_rad && row.errors.rssi_p95_db <= tolerance.rssi_db);
    choice.rows.push_back(row);
    if (!row.within) continue;
    choice.picked = ladder[i];
    const ChannelErrorStats& e = row.errors;
    choice.reason = is_reference
                        ? "no cheaper level stays within the tolerance"
                        : "cheapest level within the tolerance: p95 phase error " + fixed(e.phase_p95_rad, 4) +
                              " <= " + fixed(tolerance.phase_rad, 4) + " rad, p95 RSSI error " +
                              fixed(e.rssi_p95_db, 3) + " <= " + fixed(tolerance.rssi_db, 3) + " dB";
    choice.reason += " (" + std::to_string(choice.links) + " sampled links, " + std::to_string(e.links) +
                     " readable, vs " + ladder.back().label + ")";
    break;
  }
  // How far the reference itself can be trusted: the sampled links whose reference level is outside its validity
  // near a metal edge (core/level_validity.h). The ladder is judged against the reference all the same; the count
  // says how much of the comparison rests on links where no level is checked.
  const RaytracedChannel reference_channel(scene, ladder.back().options);
  for (const LinkBatch& b : batches)
    for (const Endpoint& tag : b.tag_ends)
      choice.links_outside_validity +=
          !level_validity(ladder.back().level, link_sight(reference_channel, b.antenna_end, tag, b.frequency_hz),
                          b.frequency_hz)
               .level_ok;
  if (choice.links_outside_validity > 0)
    choice.reason += "; " + std::to_string(choice.links_outside_validity) + " of the sampled links are outside " +
                     ladder.back().label + "'s own validity near metal (edges and edge ends, narrow obstacles, slabs, plates, plates seen edge-on; docs/fullwave.md)";
  return choice;
}

std::unique_ptr<Channel> make_rung_channel(std::shared_ptr<const Scene> scene, const FidelityRung& rung) {
  if (rung.level == ChannelLevel::kIdeal) return std::make_unique<IdealChannel>();
  return std::make_unique<RaytracedChannel>(std::move(scene), rung.options);
}

std::vector<std::string> describe(const FidelityChoice& choice) {
  std::vector<std::string> out;
  out.push_back("channel auto: picked '" + choice.picked.label + "': " + choice.reason);
  char line[256];
  std::snprintf(line, sizeof line, "  %-28s %8s %9s %14s %12s %10s  %s", "rung", "readable", "mismatch",
                "phase p95 rad", "RSSI p95 dB", "rays/link", "within");
  out.push_back(line);
  bool flips = false;
  for (const FidelityRow& r : choice.rows) {
    const ChannelErrorStats& e = r.errors;
    flips |= !std::isfinite(e.phase_p95_rad) || !std::isfinite(e.rssi_p95_db);
    std::snprintf(line, sizeof line, "  %-28s %8zu %9zu %14s %12s %10.2f  %s", r.rung.label.c_str(), e.links,
                  e.status_mismatches, error_text(e.phase_p95_rad, 4, "flips").c_str(),
                  error_text(e.rssi_p95_db, 4, "flips").c_str(), r.rays_per_link, r.within ? "yes" : "no");
    out.push_back(line);
  }
  // A link read in one channel and not in the other has no finite error: with 5 % or more of them the p95 has none.
  if (flips)
    out.push_back("  (flips: 5 % or more of the readable links are readable in only one of the rung and the reference; "
                  "their error is unbounded, so the p95 is too)");
  return out;
}

}  // namespace rfidray
