#include "core/link_sample.h"

#include <algorithm>
#include <cmath>

#include "core/reader_model.h"
#include "core/simulation.h"

namespace rfidray {

std::vector<LinkBatch> sample_link_batches(const Scenario& scenario, const SceneMotion& motion, size_t max_links) {
  const double duration = scenario_duration_s(scenario, motion);
  const size_t n_ant = scenario.antennas.size(), n_tags = scenario.tags.size();
  bool tags_static = true;
  for (const auto& t : motion.tags) tags_static = tags_static && t->is_static();
  std::vector<LinkBatch> out;
  if (n_ant == 0 || n_tags == 0) return out;
  const size_t poses_per_antenna = std::max<size_t>(1, max_links / (n_ant * n_tags));
  for (size_t a = 0; a < n_ant; ++a) {
    const AntennaSpec& spec = scenario.antennas[a];
    const ReaderParams& reader = spec.reader;
    const uint64_t n_ticks = static_cast<uint64_t>(std::floor(duration * reader.update_rate_hz + 1e-9)) + 1;
    const bool all_static = tags_static && motion.antennas[a]->is_static();
    const size_t poses = all_static ? 1 : std::min<uint64_t>(poses_per_antenna, n_ticks);
    for (size_t k = 0; k < poses; ++k) {
      // Tick at the centre of the k-th of `poses` equal spans of the run (the first tick when only one).
      const uint64_t tick = poses == 1 ? 0 : static_cast<uint64_t>((k + 0.5) * n_ticks / poses);
      const double t = std::max(static_cast<double>(tick) / reader.update_rate_hz, spec.start_s);
      LinkBatch b;
      b.antenna = a;
      b.time_s = t;
      b.frequency_hz = reader.frequencies_hz[hop_index_at(reader, t)];
      b.antenna_end = Endpoint{motion.antennas[a]->pose_at(t), reader.pattern, reader.polarization};
      std::vector<size_t> present;
      for (size_t i = 0; i < n_tags; ++i)
        if (t >= scenario.tags[i].start_s) present.push_back(i);
      b.tags_present = present.size();
      const size_t cap = std::max<size_t>(1, max_links / n_ant);
      const size_t stride = (present.size() + cap - 1) / cap;
      for (size_t k = 0; k < present.size(); k += std::max<size_t>(1, stride)) {
        const size_t i = present[k];
        const TagSpec& tag = scenario.tags[i];
        const Pose p = motion.tags[i]->pose_at(t);
        if (!((p.position - b.antenna_end.pose.position).norm() >= kMinLinkDistance_m)) continue;
        b.tags.push_back(i);
        b.tag_ends.push_back(Endpoint{p, tag.tag.pattern, tag.tag.polarization});
        b.min_readable_h2.push_back(min_readable_h2(reader, tag.tag));
      }
      if (!b.tags.empty()) out.push_back(std::move(b));
    }
  }
  return out;
}

size_t link_count(const std::vector<LinkBatch>& batches) {
  size_t n = 0;
  for (const LinkBatch& b : batches) n += b.tags.size();
  return n;
}

}  // namespace rfidray
