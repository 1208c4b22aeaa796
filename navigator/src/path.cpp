#include "mapnav/navigator/path.h"

#include <algorithm>
#include <cmath>

namespace mapnav {

std::vector<PathPoint> densePath(const Polyline2& line, double spacing) {
  std::vector<PathPoint> out;
  const double length = line.length();
  if (line.size() < 2 || !(spacing > 0)) {
    if (!line.empty()) out.push_back({line.front(), 0.0, 0.0});
    return out;
  }
  // Every vertex, plus evenly spaced points on each segment.
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const double s0 = line.arcLengthAt(i), s1 = line.arcLengthAt(i + 1);
    const int pieces = std::max(1, static_cast<int>(std::ceil((s1 - s0) / spacing)));
    for (int k = 0; k < pieces; ++k) {
      const double s = s0 + (s1 - s0) * k / pieces;
      if (!out.empty() && s - out.back().s < 1e-9) continue;
      out.push_back({line.pointAt(s), line.headingAt(s), s});
    }
  }
  out.push_back({line.back(), line.headingAt(length), length});
  return out;
}

}  // namespace mapnav
