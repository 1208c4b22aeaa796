#pragma once
// The frames of a closed loop (internal to mission/): a FrameSource over a simulated plant
// (sim/plant.h) and the vehicle it carries. Between frames the Driver (the runner's Motion Control)
// steers the vehicle every control step; each frame is rendered at the true pose, with the odometry
// sensor's reading of the true motion since the previous frame.
#include <cstddef>

#include "mapnav/geometry/pose2.h"
#include "mapnav/navigator/vehicle.h"
#include "mapnav/sim/plant.h"

#include "drive.h"
#include "frame_source.h"

namespace mapnav::detail {

class ClosedLoopSource final : public FrameSource {
 public:
  /// The vehicle starts at `start` (world frame) with `limits`; frames and control steps follow
  /// `drive` (its max_frames ends the source); `expected_frames` is the progress bar's estimate.
  ClosedLoopSource(SimulatedPlant& plant, const Pose2& start, const VehicleLimits& limits,
                   const DriveLoopOptions& drive, std::size_t expected_frames);

  bool next(Driver& driver, SourceFrame& frame) override;
  std::size_t expectedFrames() const override { return expected_frames_; }

  /// Where the vehicle truly is.
  const Pose2& pose() const { return vehicle_.pose(); }
  /// The driver said it arrived (not a limit, not the modules).
  bool finished() const { return finished_; }
  std::size_t frames() const { return drive_.frames(); }
  double distance_m() const { return drive_.distance_m(); }  ///< driven (true), m
  double duration_s() const { return drive_.t(); }           ///< mission time at the end, s

 private:
  SimulatedPlant& plant_;
  SkidSteerVehicle vehicle_;
  DriveLoopOptions options_;
  Drive drive_;
  std::size_t expected_frames_;
  bool finished_ = false;
};

}  // namespace mapnav::detail
