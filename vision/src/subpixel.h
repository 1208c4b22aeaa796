#pragma once
// Sub-pixel peaks: where a sampled score peaks between its samples.
#include <algorithm>
#include <cmath>

namespace mapnav {

/// The offset from the middle sample of the vertex of the parabola through (-1, left),
/// (0, middle), (1, right), within ±0.5; 0 when the three do not bend down (a flat top, a
/// non-finite value).
inline double parabolaPeak(double left, double middle, double right) {
  const double bend = left - 2 * middle + right;
  return std::isfinite(bend) && bend < 0 ? std::clamp(0.5 * (left - right) / bend, -0.5, 0.5) : 0.0;
}

}  // namespace mapnav
