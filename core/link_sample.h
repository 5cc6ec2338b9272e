#pragma once
// A deterministic sample of a scenario's antenna–tag links at poses the simulation will visit, grouped by
// antenna pose (one batch = one Channel::one_way call). Used to judge channel settings before a run
// (`channel: auto`, raytrace/fidelity.h) without simulating.
#include <cstddef>
#include <vector>

#include "core/channel.h"
#include "core/scenario.h"
#include "core/simulation.h"

namespace rfidray {

struct LinkBatch {
  size_t antenna = 0;  // index into Scenario::antennas
  double time_s = 0.0;
  double frequency_hz = 0.0;  // the carrier in use at time_s
  Endpoint antenna_end;
  size_t tags_present = 0;               // tags present at time_s (the batch may hold a subset of them)
  std::vector<size_t> tags;              // indices into Scenario::tags (present at time_s)
  std::vector<Endpoint> tag_ends;        // their endpoints at time_s
  std::vector<double> min_readable_h2;   // per tag: min_readable_h2(reader, tag)
};

// About `max_links` links (at least one pose per antenna): for each antenna, poses at evenly spaced ticks over
// the scenario (one pose when antenna and tags are all static), every present tag at each — or, when there are
// more tags than max_links / antennas, every k-th of them. Tags at the antenna are left out (the simulation
// itself reports them).
// `motion` is build_motion(scenario).
std::vector<LinkBatch> sample_link_batches(const Scenario& scenario, const SceneMotion& motion, size_t max_links);

size_t link_count(const std::vector<LinkBatch>& batches);

}  // namespace rfidray
