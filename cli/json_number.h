#pragma once
// A number for the commands' JSON: JSON has no NaN or infinity, so a value that is not finite (not measured, no
// solution) is written as null. Pure; never throws.
#include <cmath>
#include <nlohmann/json.hpp>

namespace rfidray::cli {

inline nlohmann::json number_or_null(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace rfidray::cli
