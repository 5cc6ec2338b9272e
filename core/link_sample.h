#pragma once
// A deterministic sample of a scenario's antenna–tag links at poses the simulation will visit, grouped by
// antenna pose (one batch = one Channel::one_way call). Used to judge channel settings before a run
// (`channel: auto`, raytrace/fidelity.h) without simulating.
#include <cstddef>
#include <vector>

#include "core/channel.h"
#include "core/scenario.h"

namespace rfidray {

struct LinkBatch {
  size_t antenna = 0;  // index into Scenario::antennas
  double time_s = 0.0;
  double frequency_hz = 0.0;  // the carrier in use at time_s
  Endpoint antenna_end;
  std::vector<size_t> tags;              // indices into Scenario::tags (present at time_s)
  std::vector<Endpoint> tag_ends;        // their endpoints at time_s
  std::vector<double> min_readable_h2;   // per tag: min_readable_h2(reader, tag)
};

// About `max_links` links (at least one pose per antenna): for each antenna, poses at evenly spaced ticks over
// the scenario (one pose when antenna and tags are all static), every present tag at each. Tags at the
// antenna are left out (the simulation itself reports them).
std::vector<LinkBatch> sample_link_batches(const Scenario& scenario, size_t max_links);

size_t link_count(const std::vector<LinkBatch>& batches);

}  // namespace rfidray
