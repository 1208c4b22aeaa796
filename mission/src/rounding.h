#pragma once
// Figures rounded for the JSON outputs and the trace: a fixed number of decimals keeps their bytes
// independent of a computation's last bits; + 0.0 turns -0 into 0.
#include <cmath>

namespace mapnav::detail {

/// `x` rounded to a multiple of 1 / `scale` (scale 1e4: 4 decimals).
inline double roundTo(double x, double scale) { return std::round(x * scale) / scale + 0.0; }

}  // namespace mapnav::detail
