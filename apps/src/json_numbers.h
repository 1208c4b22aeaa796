#pragma once
// Numbers in the commands' JSON output. Include only where JSON is written (it includes core/json.h).
#include <cmath>
#include <optional>

#include "mapnav/core/json.h"

namespace mapnav::cli {

/// `v` rounded to `digits` decimals, or null.
inline Json roundedOrNull(const std::optional<double>& v, int digits) {
  if (!v) return nullptr;
  const double scale = std::pow(10.0, digits);
  return std::round(*v * scale) / scale;
}

}  // namespace mapnav::cli
