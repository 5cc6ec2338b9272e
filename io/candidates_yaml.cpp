#include "io/candidates_yaml.h"

#include <cmath>

#include "core/units.h"
#include "io/checked_yaml.h"
#include "io/tag_generators.h"

namespace rfidray::io {
namespace {

Quat rpy(double roll_deg, double pitch_deg, double yaw_deg) {
  const double d = kPi / 180.0;
  return Quat(Eigen::AngleAxisd(yaw_deg * d, Vec3::UnitZ()) * Eigen::AngleAxisd(pitch_deg * d, Vec3::UnitY()) *
              Eigen::AngleAxisd(roll_deg * d, Vec3::UnitX()));
}

}  // namespace

CandidateFile load_candidates(const std::string& path) {
  const YAML::Node root = load_yaml_file(path, "candidates file");
  if (!root.IsDefined() || root.IsNull()) throw InputError(path + ": empty candidates file");
  const YamlFile src(path);
  YamlMap top(src, root, "");
  CandidateFile out;
  out.template_antenna = top.string("template", "");
  auto check_count = [&](const YAML::Node& n, const std::string& field) {
    if (out.mounts.size() > kMaxCandidates)
      throw src.error(n, field, "more than " + std::to_string(kMaxCandidates) + " candidates");
  };
  if (auto mounts = top.get("mounts")) {
    if (!mounts->IsSequence()) throw src.error(*mounts, "mounts", "must be a list");
    for (size_t i = 0; i < mounts->size(); ++i) {
      const std::string field = "mounts[" + std::to_string(i) + "]";
      YamlMap m(src, (*mounts)[i], field);
      CandidateMount c;
      c.name = m.string("name", "m" + std::to_string(i));
      c.pose.position = src.point(m.required("position"), m.field("position"));
      if (auto f = m.get_one({"rpy_deg", "yaw_deg"})) {
        if (f->first == "yaw_deg") {
          c.pose.orientation = rpy(0, 0, src.number(f->second, m.field("yaw_deg")));
        } else {
          const Vec3 a = src.point(f->second, m.field("rpy_deg"));
          c.pose.orientation = rpy(a.x(), a.y(), a.z());
        }
      }
      m.finish();
      out.mounts.push_back(c);
      check_count((*mounts)[i], field);
    }
  }
  if (auto grids = top.get("grids")) {
    if (!grids->IsSequence()) throw src.error(*grids, "grids", "must be a list");
    for (size_t i = 0; i < grids->size(); ++i) {
      const std::string field = "grids[" + std::to_string(i) + "]";
      YamlMap m(src, (*grids)[i], field);
      const std::string name = m.string("name", "g" + std::to_string(i));
      TagGrid g;
      g.min = src.point(m.required("min"), m.field("min"));
      g.max = src.point(m.required("max"), m.field("max"));
      g.step_m = src.number(m.required("step_m"), m.field("step_m"));
      std::vector<double> yaws{0.0};
      if (auto y = m.get("yaw_deg")) yaws = y->IsSequence() ? src.numbers(*y, m.field("yaw_deg"))
                                                           : std::vector<double>{src.number(*y, m.field("yaw_deg"))};
      if (yaws.empty()) throw src.error(*m.get("yaw_deg"), m.field("yaw_deg"), "must not be empty");
      const double pitch = m.number("pitch_deg", 0.0);
      m.finish();
      const std::vector<Vec3> pts = src.located((*grids)[i], [&] {
        return grid_points(g, field, kMaxCandidates / yaws.size() + 1);
      });
      for (size_t p = 0; p < pts.size(); ++p)
        for (size_t k = 0; k < yaws.size(); ++k) {
          out.mounts.push_back({name + "_" + std::to_string(p) + "_" + std::to_string(k), Pose{pts[p], rpy(0, pitch, yaws[k])}});
          check_count((*grids)[i], field);
        }
    }
  }
  if (auto robots = top.get("robot_mounts")) {
    if (!robots->IsSequence()) throw src.error(*robots, "robot_mounts", "must be a list");
    for (size_t i = 0; i < robots->size(); ++i) {
      const std::string field = "robot_mounts[" + std::to_string(i) + "]";
      YamlMap m(src, (*robots)[i], field);
      const std::string name = m.string("name", "r" + std::to_string(i));
      const std::string robot = m.string("robot", "");
      const std::string tmpl = m.string("template", "");
      auto list = [&](const char* key, std::vector<double> fallback) {
        const auto n = m.get(key);
        if (!n) return fallback;
        std::vector<double> v = n->IsSequence() ? src.numbers(*n, m.field(key))
                                                : std::vector<double>{src.number(*n, m.field(key))};
        if (v.empty()) throw src.error(*n, m.field(key), "must not be empty");
        return v;
      };
      const auto height_node = m.required("height_m");
      const std::vector<double> heights = list("height_m", {});
      for (double h : heights)
        if (!(h >= 0.0 && h <= 1e3)) throw src.error(height_node, m.field("height_m"), "heights must be in [0, 1000] m");
      const std::vector<double> yaws = list("yaw_deg", {0.0}), pitches = list("pitch_deg", {0.0});
      double offset[2] = {0.0, 0.0};
      if (auto o = m.get("offset_m")) {
        const std::vector<double> v = src.numbers(*o, m.field("offset_m"));
        if (v.size() != 2) throw src.error(*o, m.field("offset_m"), "expected [x, y] (m)");
        offset[0] = v[0], offset[1] = v[1];
      }
      m.finish();
      const double combos = double(heights.size()) * double(yaws.size()) * double(pitches.size());
      if (double(out.mounts.size()) + combos > double(kMaxCandidates))
        throw src.error((*robots)[i], field, "more than " + std::to_string(kMaxCandidates) + " candidates");
      for (size_t h = 0; h < heights.size(); ++h)
        for (size_t y = 0; y < yaws.size(); ++y)
          for (size_t p = 0; p < pitches.size(); ++p) {
            CandidateMount c;
            c.name = name + "_" + std::to_string(h) + "_" + std::to_string(y) + "_" + std::to_string(p);
            c.pose = Pose{Vec3(offset[0], offset[1], heights[h]), rpy(0, pitches[p], yaws[y])};
            c.on_robot = true;
            c.robot = robot;
            c.template_antenna = tmpl;
            out.mounts.push_back(std::move(c));
          }
    }
  }
  top.finish();
  if (out.mounts.empty()) throw InputError(path + ": no candidates (give mounts, grids and/or robot_mounts)");
  return out;
}

}  // namespace rfidray::io
