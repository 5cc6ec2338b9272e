#pragma once
// The readings CSV, written by `rfidray simulate` (and the live bridge) and read by `localize` and the tests:
// one writer and one reader of one row type. One file per antenna — the seed data collector's column order
// first, then ours:
//   time,posx,posy,posz,q1,q2,q3,q4,name,dist,phase,rssi,antenna,frequency_hz,channel
// time s · antenna position m · antenna orientation quaternion x,y,z,w · tag name · true distance m ·
// phase rad in [0, 2π) · RSSI (paper model: eq. 5 value; physical: dBm) · antenna name · carrier Hz ·
// hop index (the column keeps the name `channel`, which users' scripts read). Fixed decimals, so the bytes
// depend on nothing but the values.
// Ground truth: tags.csv `name,x,y,z` (t = 0) and, for moving tags, tags_trajectory.csv `time,name,x,y,z`.
// Readers throw InputError "FILE:LINE: column 'NAME': what". Functions are thread-safe (no shared state).
#include <filesystem>
#include <map>
#include <ostream>
#include <string>
#include <vector>

#include "core/geometry.h"
#include "core/scenario.h"
#include "core/simulation.h"
#include "localization/observations.h"

namespace rfidray::io {

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

// One row of a readings file. `distance_m` is ground truth: parsed (so a broken file is reported) but never
// handed to a localization method — group_by_tag() does not copy it.
struct ReadingRow {
  int line = 0;  // 1-based line in the file
  double time_s = 0.0;
  Pose antenna_pose;
  std::string tag;
  double distance_m = 0.0;
  double phase_rad = 0.0;  // [0, 2π) or (−π, π]
  double rssi = 0.0;
  std::string antenna;        // "" when the column is absent
  double frequency_hz = 0.0;  // 0 when the column is absent (the caller's default applies)
  int hop_index = -1;         // the `channel` column; −1 when absent
};

// Header and rows of readings that did not come from a simulation (`rfidray import`): the same columns and
// number formatting as the writer above. `line` is not written.
void write_readings_csv(std::ostream& out, const std::vector<ReadingRow>& rows);

// The 12 seed columns are required in order; `antenna`, `frequency_hz` (or `frequency`, Hz) and `channel` are
// read when present, other columns ignored.
std::vector<ReadingRow> read_readings_csv(const std::filesystem::path& file);
// name → position; header name,x,y,z.
std::map<std::string, Vec3> read_truth_csv(const std::filesystem::path& file);

// Splits one CSV line (double quotes allowed around fields).
std::vector<std::string> split_csv_line(const std::string& line);

// One TagReads per tag name (sorted), one ReadGroup per (file, antenna, hop index, frequency), reads sorted by
// time.
std::vector<loc::TagReads> group_by_tag(const std::vector<std::vector<ReadingRow>>& files, double default_frequency_hz);

}  // namespace rfidray::io
