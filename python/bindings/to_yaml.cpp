// Python values → YAML nodes for the library's checked readers (io/checked_yaml.h).
#include <pybind11/numpy.h>

#include <cmath>
#include <cstdio>

#include "core/error.h"
#include "python/bindings/bindings.h"

namespace rfidray::py {

YAML::Node to_yaml(pyb::handle value, const std::string& field) {
  if (value.is_none()) return YAML::Node(YAML::NodeType::Null);
  if (pyb::isinstance<pyb::bool_>(value)) return YAML::Node(value.cast<bool>() ? "true" : "false");
  if (pyb::isinstance<pyb::int_>(value)) return YAML::Node(pyb::str(value).cast<std::string>());
  if (pyb::isinstance<pyb::float_>(value)) {
    // Shortest text that reads back as the same double; non-finite values are spelt so the reader rejects them.
    const double v = value.cast<double>();
    if (!std::isfinite(v)) return YAML::Node(std::isnan(v) ? "nan" : v > 0 ? "inf" : "-inf");
    return YAML::Node(pyb::repr(value).cast<std::string>());
  }
  if (pyb::isinstance<pyb::str>(value)) return YAML::Node(value.cast<std::string>());
  if (pyb::isinstance<pyb::dict>(value)) {
    YAML::Node map(YAML::NodeType::Map);
    for (auto item : value.cast<pyb::dict>()) {
      const std::string key = pyb::str(item.first).cast<std::string>();
      map[key] = to_yaml(item.second, field.empty() ? key : field + "." + key);
    }
    return map;
  }
  // NumPy arrays and scalars through their Python values (tolist / item).
  if (pyb::hasattr(value, "tolist") && !pyb::isinstance<pyb::list>(value)) return to_yaml(value.attr("tolist")(), field);
  if (pyb::isinstance<pyb::list>(value) || pyb::isinstance<pyb::tuple>(value)) {
    YAML::Node seq(YAML::NodeType::Sequence);
    size_t i = 0;
    for (auto item : value) seq.push_back(to_yaml(item, field + "[" + std::to_string(i++) + "]"));
    return seq;
  }
  throw field_error(field, "cannot use a value of type " + pyb::str(value.get_type().attr("__name__")).cast<std::string>());
}

}  // namespace rfidray::py
