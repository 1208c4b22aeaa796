#pragma once
// The vehicle's motion over one interval (between two camera frames, or one control step), in the
// vehicle's own frame: how far it drove along its heading and how much that heading turned. The one
// type for a motion increment: odometry as the sensors report it (a replay log's `odometry`, the
// simulated sensor's reading), the true motion the simulator drove, and the filter's prediction input.
// Distances are metres, angles radians (a replay log stores degrees; its reader converts).
#include <cmath>

#include "mapnav/geometry/pose2.h"

namespace mapnav {

struct MotionIncrement {
  double distance_m = 0.0;    ///< driven over the interval, m (negative: backwards); the first
                              ///< frame of a log: since the start
  double dheading_rad = 0.0;  ///< heading change over the same interval, left (counter-clockwise) positive, rad

  bool operator==(const MotionIncrement&) const = default;
};

/// The vehicle's pose after `m` in its own frame before it: the distance driven along the
/// mid-step heading, the model PoseFilter::predict uses.
inline Pose2 stepPose(const MotionIncrement& m) {
  const double d = m.distance_m, dh = m.dheading_rad;
  return Pose2(d * std::cos(0.5 * dh), d * std::sin(0.5 * dh), dh);
}

}  // namespace mapnav
