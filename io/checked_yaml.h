#pragma once
// The one checked YAML reader of rfidray's input files (scenarios, material maps, sensor parameters from SDF):
// every value is read through a YamlFile, which turns a node and a field path into an InputError
// "FILE:LINE: field 'a.b[2]': what", and every map through a YamlMap, whose finish() reports the keys nobody
// read (with a "did you mean") — a typo never falls back to a default. Numbers must be finite.
// Not thread-safe per object; separate objects are independent.
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cstdio>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/geometry.h"
#include "core/limits.h"
#include "core/number_text.h"

namespace rfidray::io {

// Parses a YAML file; `what` names it in messages ("scenario file", "material map"). Throws InputError
// "PATH: cannot open WHAT (no such file | unreadable | not a regular file)" or "PATH:LINE:COL: malformed YAML: ...".
YAML::Node load_yaml_file(const std::string& path, const std::string& what);
// The same on text already read; `source` names it.
YAML::Node parse_yaml_text(const std::string& text, const std::string& source);

// Edit distance, for "did you mean" on unknown keys.
inline size_t edit_distance(const std::string& a, const std::string& b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diag + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diag = up;
    }
  }
  return row[b.size()];
}

// The file being parsed: turns a node and a field path into a located error.
class YamlFile {
 public:
  // use_marks = false: the nodes were built in code (another front end), so their marks say nothing and
  // every message is located by `file` alone (which then names the place, e.g. "world.sdf:42: sensor 'x'").
  explicit YamlFile(std::string file, bool use_marks = true) : file_(std::move(file)), use_marks_(use_marks) {}
  const std::string& file() const { return file_; }

  std::string at(const YAML::Node& n) const {
    const YAML::Mark m = n.Mark();
    if (!use_marks_ || m.line < 0) return file_ + ": ";
    return file_ + ":" + std::to_string(m.line + 1) + ": ";
  }
  int line(const YAML::Node& n) const { return !use_marks_ || n.Mark().line < 0 ? 0 : n.Mark().line + 1; }
  InputError error(const YAML::Node& n, const std::string& field, const std::string& what) const {
    return InputError(at(n) + "field '" + field + "': " + what);
  }
  // Runs f; an InputError it throws (e.g. from validate()) gets this node's location in front.
  template <typename F>
  auto located(const YAML::Node& n, F&& f) const {
    try {
      return f();
    } catch (const InputError& e) {
      throw InputError(at(n) + e.what());
    }
  }

  std::string scalar(const YAML::Node& n, const std::string& field) const {
    if (!n.IsScalar()) throw error(n, field, "must be a single value");
    return n.Scalar();
  }
  double number(const YAML::Node& n, const std::string& field) const {
    const std::string s = scalar(n, field);
    double v = 0.0;
    try {
      v = n.as<double>();
    } catch (const YAML::Exception&) {
      throw error(n, field, "must be a number (got '" + clip(s) + "')");
    }
    if (!std::isfinite(v)) throw error(n, field, "must be a finite number (got '" + clip(s) + "')");
    return v;
  }
  long long integer(const YAML::Node& n, const std::string& field) const {
    const std::string s = scalar(n, field);
    try {
      return n.as<long long>();
    } catch (const YAML::Exception&) {
      throw error(n, field, "must be an integer (got '" + clip(s) + "')");
    }
  }
  bool boolean(const YAML::Node& n, const std::string& field) const {
    const std::string s = scalar(n, field);
    try {
      return n.as<bool>();
    } catch (const YAML::Exception&) {
      throw error(n, field, "must be true or false (got '" + clip(s) + "')");
    }
  }
  std::vector<double> numbers(const YAML::Node& n, const std::string& field) const {
    if (!n.IsSequence()) throw error(n, field, "must be a list of numbers");
    std::vector<double> v;
    for (size_t i = 0; i < n.size(); ++i) v.push_back(number(n[i], field + "[" + std::to_string(i) + "]"));
    return v;
  }
  Vec3 point(const YAML::Node& n, const std::string& field, bool allow_2d = false) const {
    const std::vector<double> v = numbers(n, field);
    if (allow_2d && v.size() == 2) {
      for (size_t i = 0; i < 2; ++i)
        if (!limits::coordinate_ok(v[i]))
          throw error(n[i], field, "must be within ±" + num(limits::kMaxCoordinateM) + " (got " + num(v[i]) + ")");
      return Vec3(v[0], v[1], 0.0);
    }
    if (v.size() != 3)
      throw error(n, field, std::string("needs ") + (allow_2d ? "2 or 3" : "3") + " numbers (got " +
                                std::to_string(v.size()) + ")");
    // Positions (and every other 3-vector) within the coordinate range: no overflow downstream.
    for (size_t i = 0; i < v.size(); ++i)
      if (!limits::coordinate_ok(v[i]))
        throw error(n[i], field, "must be within ±" + num(limits::kMaxCoordinateM) + " (got " + num(v[i]) + ")");
    return Vec3(v[0], v[1], v[2]);
  }

 private:
  std::string file_;
  bool use_marks_ = true;
};

// A YAML map whose keys are checked: every key must be read by the parser, or finish() reports it.
class YamlMap {
 public:
  YamlMap(const YamlFile& src, const YAML::Node& node, std::string field) : src_(src), node_(node), field_(std::move(field)) {
    if (!node_.IsMap()) throw src_.error(node_, field_.empty() ? "(top level)" : field_, "must be a map of key: value");
  }
  const YAML::Node& node() const { return node_; }
  const YamlFile& src() const { return src_; }
  std::string field(const std::string& key) const { return field_.empty() ? key : field_ + "." + key; }

  std::optional<YAML::Node> get(const std::string& key) {
    known_.insert(key);
    const YAML::Node n = node_[key];
    if (!n.IsDefined() || n.IsNull()) return std::nullopt;
    return n;
  }
  // One of several names for the same parameter (ours and the seed plugin's); giving two is an error.
  std::optional<std::pair<std::string, YAML::Node>> get_one(std::initializer_list<const char*> keys) {
    std::optional<std::pair<std::string, YAML::Node>> found;
    for (const char* k : keys) {
      auto n = get(k);
      if (!n) continue;
      if (found)
        throw src_.error(*n, field(k), "give only one of '" + found->first + "' and '" + k + "' (same parameter)");
      found = std::make_pair(std::string(k), *n);
    }
    return found;
  }
  // Marks keys as part of the format here without reading them (so "known keys" lists them).
  void allow(std::initializer_list<const char*> keys) {
    for (const char* k : keys) known_.insert(k);
  }
  bool has(const std::string& key) const {
    const YAML::Node n = node_[key];
    return n.IsDefined() && !n.IsNull();
  }

  double number(std::initializer_list<const char*> keys, double fallback) {
    auto f = get_one(keys);
    return f ? src_.number(f->second, field(f->first)) : fallback;
  }
  double number(const char* key, double fallback) { return number({key}, fallback); }
  // A number that must be > 0 (or ≥ 0 when allow_zero).
  double positive(std::initializer_list<const char*> keys, double fallback, bool allow_zero = false) {
    auto f = get_one(keys);
    if (!f) return fallback;
    const double v = src_.number(f->second, field(f->first));
    if (allow_zero ? v < 0.0 : v <= 0.0)
      throw src_.error(f->second, field(f->first), std::string("must be ") + (allow_zero ? ">= 0" : "> 0") +
                                                       " (got " + num(v) + ")");
    return v;
  }
  double non_negative(std::initializer_list<const char*> keys, double fallback) { return positive(keys, fallback, true); }
  std::string string(const char* key, const std::string& fallback) {
    auto n = get(key);
    return n ? src_.scalar(*n, field(key)) : fallback;
  }
  YAML::Node required(const char* key) {
    auto n = get(key);
    if (n) return *n;
    // A misspelt required key is reported as the typo, not as a missing key.
    for (auto it = node_.begin(); it != node_.end(); ++it) {
      const std::string k = it->first.Scalar();
      if (!known_.count(k) && edit_distance(k, key) <= 2)
        throw src_.error(it->first, field(clip(k)), "unknown key '" + clip(k) + "' (did you mean '" + key + "'?)");
    }
    throw src_.error(node_, field(key), "is required");
  }

  void finish() const {
    std::vector<std::string> unknown;
    YAML::Node first;
    for (auto it = node_.begin(); it != node_.end(); ++it) {
      const std::string k = it->first.Scalar();
      if (known_.count(k)) continue;
      if (unknown.empty()) first = it->first;
      unknown.push_back(k);
    }
    if (unknown.empty()) return;
    std::string msg = "unknown key";
    msg += unknown.size() > 1 ? "s " : " ";
    for (size_t i = 0; i < unknown.size(); ++i) msg += (i ? ", '" : "'") + clip(unknown[i]) + "'";
    // Suggest the closest known key for the first one (typos).
    std::string best;
    size_t best_d = 3;
    for (const std::string& k : known_) {
      const size_t d = edit_distance(unknown[0], k);
      if (d < best_d) best_d = d, best = k;
    }
    if (!best.empty()) msg += " (did you mean '" + best + "'?)";
    std::string known;
    for (const std::string& k : known_) known += (known.empty() ? "" : ", ") + k;
    msg += "; known keys here: " + known;
    throw src_.error(first, field(clip(unknown[0])), msg);
  }

 private:
  const YamlFile& src_;
  YAML::Node node_;
  std::string field_;
  std::set<std::string> known_;
};

}  // namespace rfidray::io
