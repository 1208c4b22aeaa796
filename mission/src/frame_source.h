#pragma once
// Where the runner's camera frames come from (internal to mission/): a FrameSource yields them one
// at a time — a recorded log (replay_source.h) or a simulated plant driven in closed loop
// (closed_loop_source.h) — and the runner is one loop over it: the next frame, the four modules
// (module_loop.h), and, for a plant, Motion Control driving it to the next frame (the Driver).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/geometry/motion.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/mission/runner.h"
#include "mapnav/navigator/vehicle.h"
#include "mapnav/image/image.h"

namespace mapnav::detail {

/// One camera frame as the modules take it.
struct SourceFrame {
  std::size_t index = 0;         ///< replay: the log's frame index (frames skipped count); closed loop: frames before
  double t = 0;                  ///< mission time, s
  Image rgb;                     ///< 3 channels, the camera's size
  MotionIncrement odometry;      ///< measured since the previous frame delivered (the first: since the start)
  std::optional<Pose2> truth;    ///< the vehicle's true pose (world frame), when the source knows it
  std::optional<Vec2> gnss;      ///< replay: the log's GNSS fix with this frame (world frame, m) ...
  double gnss_sigma_m = 0;       ///< ... and its 1-sigma error
  std::string image;             ///< replay: the PNG, relative to the log folder ("" in closed loop)
  std::vector<LogFault> faults;  ///< the source's faults met since the previous frame, in file order
};

/// Who drives a plant between frames: the runner's Motion Control.
class Driver {
 public:
  virtual ~Driver() = default;
  /// The command for the control step at mission time `t` (s); `truth` is the true pose before it.
  virtual VehicleCommand command(double t, const Pose2& truth) = 0;
  /// True when the vehicle has arrived: the plant stops there.
  virtual bool arrived() const = 0;
};

class FrameSource {
 public:
  virtual ~FrameSource() = default;
  /// Fills `frame` with the next frame and returns true; false at the end (`frame.faults` then holds
  /// the faults met after the last frame). A plant is first driven to it by `driver`; a recording
  /// ignores the driver. Not called again after false, nor after the modules ended the mission.
  virtual bool next(Driver& driver, SourceFrame& frame) = 0;
  /// The frames expected in all, for a progress bar (a plant's is an estimate).
  virtual std::size_t expectedFrames() const = 0;
};

}  // namespace mapnav::detail
