#pragma once
// Candidate antenna mounts for `rfidray place` (YAML):
//   template: NAME            # the scenario antenna whose radio keys every candidate takes (default: the first
//                             # fixed one, else the first)
//   mounts:                   # single poses
//     - {name: door_left, position: [x, y, z], rpy_deg: [roll, pitch, yaw] | yaw_deg: Y}
//   grids:                    # poses on a grid: every point × every yaw (walls, ceiling rails, poles)
//     - {name: ceiling, min: [x, y, z], max: [x, y, z], step_m: S, yaw_deg: [0, 90, 180, 270], pitch_deg: P}
// Candidates are numbered in file order (mounts first, then each grid: points x fastest, then y, z, and for each
// point its yaws); a grid candidate's name is NAME_<point>_<yaw index>. At most kMaxCandidates.
// Throws InputError "FILE:LINE: field '…': …" (io/checked_yaml.h).
#include <string>
#include <vector>

#include "core/geometry.h"

namespace rfidray::io {

inline constexpr size_t kMaxCandidates = 100'000;

struct CandidateMount {
  std::string name;
  Pose pose;  // boresight = local +X
};

struct CandidateFile {
  std::string template_antenna;  // "" = default
  std::vector<CandidateMount> mounts;
};

CandidateFile load_candidates(const std::string& path);

}  // namespace rfidray::io
