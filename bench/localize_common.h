#pragma once
// Shared by the localization benches: simulation records → per-tag phase histories (never the true
// distance), and timed runs of one method.
#include <chrono>
#include <map>
#include <string>
#include <vector>

#include "localization/methods.h"
#include "core/scenario.h"
#include "core/simulation.h"

namespace rfidray::bench {

// One TagReads per tag that was read (indexed like scenario.tags; empty groups for unread tags), one group
// per channel frequency. ReadRecord::distance_m is deliberately not copied.
inline std::vector<loc::TagReads> tag_reads(const Scenario& scenario, const AntennaSpec& antenna,
                                            const AntennaResult& result) {
  std::vector<loc::TagReads> out(scenario.tags.size());
  std::vector<std::map<double, size_t>> group_of(scenario.tags.size());
  for (size_t i = 0; i < out.size(); ++i) out[i].tag = scenario.tags[i].tag.name;
  for (const ReadRecord& r : result.reads) {
    loc::TagReads& t = out[r.tag];
    auto [it, inserted] = group_of[r.tag].emplace(r.frequency_hz, t.groups.size());
    if (inserted) t.groups.push_back(loc::ReadGroup{antenna.reader.name, r.frequency_hz, {}});
    t.groups[it->second].reads.push_back(
        loc::PhaseRead{r.time_s, r.antenna_pose.position, r.antenna_pose.orientation, r.reading.phase_rad});
  }
  return out;
}

struct TimedResult {
  loc::LocalizeResult result;
  double time_ms = 0.0;
};

inline TimedResult timed_localize(loc::Method m, const loc::TagReads& tag, const loc::LocalizeOptions& o) {
  const auto start = std::chrono::steady_clock::now();
  TimedResult t;
  t.result = loc::localize(m, tag, o);
  t.time_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return t;
}

}  // namespace rfidray::bench
