#pragma once
// CSV output of `rfidray simulate`, and reading it back.
// Readings, one file per antenna — the seed data collector's column order first, then ours:
//   time,posx,posy,posz,q1,q2,q3,q4,name,dist,phase,rssi,antenna,frequency_hz,channel
// time s · antenna position m · antenna orientation quaternion x,y,z,w · tag name · true distance m ·
// phase rad in [0, 2π) · RSSI (paper model: eq. 5 value; physical: dBm) · antenna name · carrier Hz ·
// hop channel index. Fixed decimals, so the bytes depend on nothing but the values.
// Ground truth: tags.csv `name,x,y,z` (t = 0) and, for moving tags, tags_trajectory.csv `time,name,x,y,z`.
#include <ostream>
#include <string>
#include <vector>

#include "core/scenario.h"
#include "core/simulation.h"

namespace rfidray::cli {

inline constexpr const char* kReadingsHeader =
    "time,posx,posy,posz,q1,q2,q3,q4,name,dist,phase,rssi,antenna,frequency_hz,channel";

void write_readings_csv(std::ostream& out, const Scenario& scenario, size_t antenna, const AntennaResult& result);
// The rows alone (no header), for writers that append as readings arrive (the Gazebo bridge).
void write_readings_rows(std::ostream& out, const Scenario& scenario, size_t antenna,
                         const std::vector<ReadRecord>& reads);
void write_tags_csv(std::ostream& out, const Scenario& scenario, const SceneMotion& motion);
// Moving tags sampled every 1/rate_hz s over [0, duration_s], while present. Header only when none moves.
void write_tag_trajectories_csv(std::ostream& out, const Scenario& scenario, const SceneMotion& motion,
                                double duration_s, double rate_hz);
bool has_moving_tags(const SceneMotion& motion);

// One row of a readings CSV.
struct CsvReading {
  double time_s = 0.0;
  Pose antenna_pose;
  std::string tag;
  double distance_m = 0.0, phase_rad = 0.0, rssi = 0.0;
  std::string antenna;
  double frequency_hz = 0.0;
  int channel = 0;
};
// Reads a readings CSV (the 12 seed columns are required, ours optional). Throws InputError "FILE:LINE: ...".
std::vector<CsvReading> read_readings_csv(const std::string& path);

}  // namespace rfidray::cli
