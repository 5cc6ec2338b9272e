#include "cli/number_list.h"

#include <cmath>
#include <sstream>

#include "core/error.h"
#include "core/limits.h"

namespace rfidray::cli {

std::vector<double> parse_number_list(const std::string& text, const std::string& option, bool coordinates) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) {
    size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    const bool ok = coordinates ? limits::coordinate_ok(v) : std::isfinite(v);
    if (used == 0 || used != item.size() || !ok)
      throw InputError("option " + option + ": '" + clip(item) + "' is not a " +
                       (coordinates ? "coordinate" : "number") + " (in '" + clip(text) + "')");
    out.push_back(v);
  }
  return out;
}

}  // namespace rfidray::cli
