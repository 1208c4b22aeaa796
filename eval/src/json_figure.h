#pragma once
// A figure in eval's JSON outputs (internal to eval/): 4 decimals, null when undefined.
#include <cmath>
#include <optional>

#include "mapnav/core/json.h"

namespace mapnav {

inline Json figure(const std::optional<double>& v) {
  if (!v) return nullptr;
  return std::round(*v * 1e4) / 1e4;
}

}  // namespace mapnav
