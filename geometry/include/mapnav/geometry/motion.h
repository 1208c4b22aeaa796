#pragma once
// The vehicle's motion over one interval (between two camera frames, or one control step), in the
// vehicle's own frame: how far it drove along its heading and how much that heading turned. The one
// type for a motion increment: odometry as the sensors report it (a replay log's `odometry`, the
// simulated sensor's reading), the true motion the simulator drove, and the filter's prediction input.
// Distances are metres, angles radians (a replay log stores degrees; its reader converts).

namespace mapnav {

struct MotionIncrement {
  double distance_m = 0.0;    ///< driven over the interval, m (negative: backwards); the first
                              ///< frame of a log: since the start
  double dheading_rad = 0.0;  ///< heading change over the same interval, left (counter-clockwise) positive, rad

  bool operator==(const MotionIncrement&) const = default;
};

}  // namespace mapnav
