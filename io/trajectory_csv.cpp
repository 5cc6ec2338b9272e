#include "io/trajectory_csv.h"

#include <algorithm>
#include <cmath>
#include <fstream>

#include "core/error.h"
#include "io/checked_yaml.h"
#include "io/csv_fields.h"
#include "io/readings_csv.h"
#include "core/number_text.h"

namespace rfidray::io {

namespace {

bool same_pose(const Pose& a, const Pose& b) {
  // q and −q are one orientation.
  return a.position == b.position && std::abs(std::abs(a.orientation.dot(b.orientation)) - 1.0) < 1e-12;
}

std::string span_text(const RecordedTrajectory& t) {
  return t.source() + ": " + num(t.start_s()) + " .. " + num(t.end_s()) + " s";
}

}  // namespace

Quat quat_from_rpy(const Vec3& rpy_rad) {
  return Quat(Eigen::AngleAxisd(rpy_rad.z(), Vec3::UnitZ()) * Eigen::AngleAxisd(rpy_rad.y(), Vec3::UnitY()) *
              Eigen::AngleAxisd(rpy_rad.x(), Vec3::UnitX()));
}

RecordedTrajectory::RecordedTrajectory(std::string source, std::vector<TrajectorySample> samples)
    : source_(std::move(source)), samples_(std::move(samples)) {
  if (samples_.empty()) throw InputError(source_ + ": trajectory has no samples");
  for (size_t i = 0; i < samples_.size(); ++i) {
    const TrajectorySample& s = samples_[i];
    if (!std::isfinite(s.time_s) || !s.pose.position.allFinite() || !s.pose.orientation.coeffs().allFinite())
      throw InputError(located(source_, s.line) + "trajectory sample is not finite");
    if (i == 0) continue;
    const TrajectorySample& prev = samples_[i - 1];
    if (s.time_s < prev.time_s)
      throw InputError(located(source_, s.line) + "column 'time': time goes backwards (" + num(s.time_s) +
                       " s after " + num(prev.time_s) + " s on line " + std::to_string(prev.line) +
                       "): a trajectory must be sorted by time");
    if (s.time_s == prev.time_s && !same_pose(s.pose, prev.pose))
      throw InputError(located(source_, s.line) + "column 'time': two different poses at " + num(s.time_s) +
                       " s (also line " + std::to_string(prev.line) + ")");
  }
}

Pose RecordedTrajectory::pose_at(double t, double tolerance_s) const {
  if (t < start_s()) {
    if (start_s() - t > tolerance_s)
      throw InputError("time " + num(t) + " s is " + num(start_s() - t) + " s before the start of the trajectory (" +
                       span_text(*this) + ")");
    return samples_.front().pose;
  }
  if (t >= end_s()) {
    if (t - end_s() > tolerance_s)
      throw InputError("time " + num(t) + " s is " + num(t - end_s()) + " s after the end of the trajectory (" +
                       span_text(*this) + ")");
    return samples_.back().pose;
  }
  // First sample later than t: [i-1, i] brackets t with t[i] > t[i-1], so the division below is safe even when
  // the robot stood still (equal positions) or samples repeat a time.
  const auto it = std::upper_bound(samples_.begin(), samples_.end(), t,
                                   [](double v, const TrajectorySample& s) { return v < s.time_s; });
  const TrajectorySample& b = *it;
  const TrajectorySample& a = *(it - 1);
  const double u = (t - a.time_s) / (b.time_s - a.time_s);
  Pose p;
  p.position = a.pose.position + u * (b.pose.position - a.pose.position);
  p.orientation = a.pose.orientation.slerp(u, b.pose.orientation).normalized();
  return p;
}

RecordedTrajectory read_trajectory_csv(const std::filesystem::path& path) {
  const std::string file = path.string();
  if (std::filesystem::is_directory(path)) throw InputError(file + ": is a directory, expected a trajectory CSV");
  std::ifstream in(path);
  if (!in) throw InputError(file + ": cannot open trajectory file");
  std::string text;
  int line = 0;
  // Header: the first non-blank line.
  std::vector<std::string> header;
  while (std::getline(in, text)) {
    ++line;
    if (line == 1) strip_bom(text);
    if (trim(text).empty()) continue;
    for (const std::string& h : split_csv_line(text)) header.push_back(normalized_name(h));
    break;
  }
  if (header.empty()) throw InputError(file + ": empty file (expected the header time,x,y,z,qx,qy,qz,qw)");
  const int header_line = line;
  auto column = [&](const char* name) {
    const auto it = std::find(header.begin(), header.end(), name);
    return it == header.end() ? -1 : static_cast<int>(it - header.begin());
  };
  const int c_time = column("time");
  const int c_pos[3] = {column("x"), column("y"), column("z")};
  const int c_q[4] = {column("qx"), column("qy"), column("qz"), column("qw")};
  const std::pair<int, const char*> required[] = {{c_time, "time"}, {c_pos[0], "x"}, {c_pos[1], "y"}, {c_pos[2], "z"}};
  for (const auto& [c, name] : required)
    if (c < 0)
      throw InputError(located(file, header_line) + "column '" + name +
                       "': missing (the header must name time,x,y,z and optionally qx,qy,qz,qw)");
  const int n_q = static_cast<int>(std::count_if(std::begin(c_q), std::end(c_q), [](int c) { return c >= 0; }));
  if (n_q != 0 && n_q != 4)
    throw InputError(located(file, header_line) + "column 'qx'..'qw': give all four quaternion columns or none");

  std::vector<TrajectorySample> samples;
  while (std::getline(in, text)) {
    ++line;
    if (trim(text).empty()) continue;
    const std::vector<std::string> f = split_csv_line(text);
    if (f.size() != header.size())
      throw InputError(located(file, line) + "expected " + std::to_string(header.size()) + " fields, got " +
                       std::to_string(f.size()));
    auto number = [&](int c) { return parse_finite(f[c], file, line, header[c]); };
    TrajectorySample s;
    s.line = line;
    s.time_s = number(c_time);
    s.pose.position = Vec3(number(c_pos[0]), number(c_pos[1]), number(c_pos[2]));
    if (n_q == 4) {
      const Eigen::Vector4d q(number(c_q[0]), number(c_q[1]), number(c_q[2]), number(c_q[3]));
      if (q.norm() < 1e-9) throw InputError(located(file, line) + "column 'qx'..'qw': quaternion has zero norm");
      s.pose.orientation = Quat(q[3], q[0], q[1], q[2]).normalized();
    }
    samples.push_back(s);
  }
  if (samples.empty()) throw InputError(file + ": empty file (a header but no samples)");
  return RecordedTrajectory(file, std::move(samples));
}

}  // namespace rfidray::io
