#pragma once
// What a localizer sees of one tag: its phase reads, grouped per (antenna, channel frequency), each group in
// time order. There is deliberately no true-distance field here: the CSV's `dist` column is ground truth and
// no method may use it, so the type cannot carry it.
#include <string>
#include <vector>

#include "core/geometry.h"

namespace rfidray::loc {

struct PhaseRead {
  double time_s = 0.0;
  Vec3 antenna_m = Vec3::Zero();            // antenna phase centre in the world frame
  Quat antenna_orientation = Quat::Identity();  // boresight = local +X (core/antenna_pattern.h)
  double phase_rad = 0.0;                   // [0, 2π) or (−π, π]; both accepted
};

// One phase history: one antenna on one channel. φ0 is constant inside a group, different between groups.
struct ReadGroup {
  std::string antenna;
  double frequency_hz = 865.7e6;
  std::vector<PhaseRead> reads;  // time-ordered
};

struct TagReads {
  std::string tag;
  std::vector<ReadGroup> groups;
  size_t read_count() const {
    size_t n = 0;
    for (const auto& g : groups) n += g.reads.size();
    return n;
  }
};

}  // namespace rfidray::loc
