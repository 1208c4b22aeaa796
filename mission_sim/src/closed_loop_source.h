#pragma once
// The frames of a closed loop in the simulator (internal to mission_sim/): a DrivenSource
// (mission/frame_source.h) over a simulated plant (sim/plant.h) and the vehicle it carries. Between
// frames the Driver (the runner's Motion Control) steers the vehicle every control step; each frame
// is rendered at the true pose (world frame), with the odometry sensor's reading of the true motion
// since the previous frame.
#include <cstddef>

#include "mapnav/geometry/pose2.h"
#include "mapnav/mission/frame_source.h"
#include "mapnav/navigator/vehicle.h"
#include "mapnav/sim/plant.h"

#include "drive.h"

namespace mapnav::detail {

class ClosedLoopSource final : public DrivenSource {
 public:
  /// The vehicle starts at `start` (world frame) with `limits`; frames and control steps follow
  /// `drive` (its max_frames ends the source); `expected_frames` is the progress bar's estimate.
  ClosedLoopSource(SimulatedPlant& plant, const Pose2& start, const VehicleLimits& limits,
                   const DriveLoopOptions& drive, std::size_t expected_frames);

  bool next(Driver& driver, SourceFrame& frame) override;
  std::size_t expectedFrames() const override { return expected_frames_; }

  const Pose2& pose() const override { return vehicle_.pose(); }
  bool finished() const override { return finished_; }
  std::size_t frames() const override { return drive_.frames(); }
  double distance_m() const override { return drive_.distance_m(); }
  double duration_s() const override { return drive_.t(); }
  double time_limit_s() const override { return options_.time_limit_s; }

 private:
  SimulatedPlant& plant_;
  SkidSteerVehicle vehicle_;
  DriveLoopOptions options_;
  Drive drive_;
  std::size_t expected_frames_;
  bool finished_ = false;
};

}  // namespace mapnav::detail
