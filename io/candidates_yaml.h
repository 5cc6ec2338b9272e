#pragma once
// Candidate antenna mounts for `rfidray place` (YAML):
//   template: NAME            # the scenario antenna whose radio keys every candidate takes (default: the first
//                             # fixed one, else the first)
//   mounts:                   # single poses
//     - {name: door_left, position: [x, y, z], rpy_deg: [roll, pitch, yaw] | yaw_deg: Y}
//   grids:                    # poses on a grid: every point × every yaw (walls, ceiling rails, poles)
//     - {name: ceiling, min: [x, y, z], max: [x, y, z], step_m: S, yaw_deg: [0, 90, 180, 270], pitch_deg: P}
//   robot_mounts:             # an antenna on a robot of the scenario, evaluated over the robot's whole pass:
//     - {name: arm, robot: R, height_m: [1.2, 1.68], yaw_deg: [-90, 90], pitch_deg: [0, 20],
//        offset_m: [x, y], template: NAME}
//                             # every height × yaw × pitch; yaw (about z) and pitch (about the yawed y, positive
//                             # tilts the boresight down) relative to the robot's frame (+X = its heading); offset_m
//                             # the mount's (x, y) in that frame (default [0, 0]); robot: default the scenario's
//                             # only robot; template: default the scenario's first antenna on that robot
// Candidates are numbered in file order (mounts first, then each grid: points x fastest, then y, z, and for each
// point its yaws; then each robot mount: heights, then yaws, then pitches, the last fastest); a grid candidate's
// name is NAME_<point>_<yaw index>, a robot mount's NAME_<height index>_<yaw index>_<pitch index>. At most
// kMaxCandidates.
// Throws InputError "FILE:LINE: field '…': …" (io/checked_yaml.h).
#include <string>
#include <vector>

#include "core/geometry.h"

namespace rfidray::io {

inline constexpr size_t kMaxCandidates = 100'000;

struct CandidateMount {
  std::string name;
  Pose pose;                     // boresight = local +X; in the world, or on a robot in the robot's frame
  bool on_robot = false;
  std::string robot;             // on_robot: the robot's name ("" = the scenario's only robot)
  std::string template_antenna;  // on_robot: the antenna whose radio keys it takes ("" = the default above)
};

struct CandidateFile {
  std::string template_antenna;  // "" = default
  std::vector<CandidateMount> mounts;
};

CandidateFile load_candidates(const std::string& path);

}  // namespace rfidray::io
