#include "io/reference_tags.h"

#include "core/error.h"
#include "io/antenna_file.h"

namespace rfidray::io {

void add_reference_tags(const std::vector<ReadingRow>& rows, const std::map<std::string, Vec3>& truth,
                        std::vector<loc::CalibrationSample>& samples, std::set<std::string>& antennas) {
  // 865.7 MHz only labels rows without a frequency column, as `localize` does without --frequency-hz.
  std::vector<loc::TagReads> tags = group_by_tag({rows}, 865.7e6);
  label_groups_by_antenna(tags);
  for (const loc::TagReads& t : tags) {
    const auto it = truth.find(t.tag);
    if (it == truth.end()) continue;
    for (const auto& g : t.groups) antennas.insert(g.antenna);
    samples.push_back({t, it->second});
  }
}

std::string antenna_to_calibrate(const std::string& requested, const std::set<std::string>& antennas,
                                 const std::string& field) {
  if (!requested.empty()) return requested;
  if (antennas.size() != 1)
    throw field_error(field, "the readings hold " + std::to_string(antennas.size()) + " antennas: name the one to calibrate");
  return *antennas.begin();
}

}  // namespace rfidray::io
