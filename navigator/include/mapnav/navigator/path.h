#pragma once
// A dense path for followers: the route's centre line as closely spaced points with headings and
// arc lengths, what pure pursuit and the paper's servo steer along.
#include <vector>

#include "mapnav/geometry/polyline2.h"
#include "mapnav/geometry/types.h"

namespace mapnav {

struct PathPoint {
  Vec2 position = Vec2::Zero();
  double heading = 0;  ///< radians, direction of travel
  double s = 0;        ///< arc length from the path's start, m
};

/// Points at most `spacing` apart along a polyline, with its tangent headings (the heading at a
/// vertex is that of the segment leaving it; the last point keeps the last segment's heading).
std::vector<PathPoint> densePath(const Polyline2& line, double spacing);

}  // namespace mapnav
