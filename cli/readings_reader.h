#pragma once
// Readings CSV of `rfidray simulate` and the tags' ground truth, parsed with line-numbered errors.
// Readings header: time,posx,posy,posz,q1,q2,q3,q4,name,dist,phase,rssi first (q = x,y,z,w), further
// columns optional; `antenna`, `channel` and `frequency_hz` (or `frequency`, Hz) are used for grouping.
// The `dist` column is ground truth: it is parsed (so a broken file is reported) but never handed to a
// localization method — group_by_tag() does not copy it.
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "core/geometry.h"
#include "core/localization/observations.h"

namespace rfidray::cli {

struct ReadingRow {
  int line = 0;
  double time_s = 0.0;
  Vec3 position = Vec3::Zero();
  Quat orientation = Quat::Identity();
  std::string name;
  double dist_m = 0.0;
  double phase_rad = 0.0;
  double rssi = 0.0;
  std::string antenna;
  std::string channel;
  double frequency_hz = 0.0;  // 0: column absent → the default frequency
};

// Throws InputError "<file>:<line>: <what>" (or "<file>: ..." for file-level problems).
std::vector<ReadingRow> load_localize_readings(const std::filesystem::path& file);
// name → position; header name,x,y,z.
std::map<std::string, Vec3> read_truth_csv(const std::filesystem::path& file);

// Splits one CSV line (double quotes allowed around fields).
std::vector<std::string> split_csv_line(const std::string& line);

// One TagReads per tag name (sorted), one ReadGroup per (file, antenna, channel, frequency), reads sorted by time.
std::vector<loc::TagReads> group_by_tag(const std::vector<std::vector<ReadingRow>>& files, double default_frequency_hz);

}  // namespace rfidray::cli
