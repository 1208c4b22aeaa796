// The closed-loop source: the vehicle driven between frames, each frame rendered at its true pose.
#include "closed_loop_source.h"

namespace mapnav::detail {

ClosedLoopSource::ClosedLoopSource(SimulatedPlant& plant, const Pose2& start, const VehicleLimits& limits,
                                   const DriveLoopOptions& drive, std::size_t expected_frames)
    : plant_(plant), vehicle_(start, limits), options_(drive), drive_(vehicle_, drive),
      expected_frames_(expected_frames) {}

bool ClosedLoopSource::next(Driver& driver, SourceFrame& frame) {
  frame = SourceFrame{};
  if (options_.max_frames > 0 && drive_.frames() >= options_.max_frames) return false;
  const Drive::Step step = drive_.toNextFrame([&](double t) { return driver.command(t, vehicle_.pose()); },
                                              [&] { return driver.arrived(); });
  if (step.stop != Drive::Stop::Frame) {
    finished_ = step.stop == Drive::Stop::Finished;
    return false;
  }
  frame.index = drive_.frames() - 1;
  frame.t = drive_.t();
  frame.truth = vehicle_.pose();
  frame.truth_on_map = plant_.truthOnMap(vehicle_.pose());
  frame.rgb = plant_.render(vehicle_.pose(), frame.t).rgb;  // not in the latency
  frame.odometry = plant_.odometry(step.motion, step.dt_s);
  if (const std::optional<GnssFix> fix = plant_.gnss(vehicle_.pose().translation(), frame.t)) {
    frame.gnss = fix->position;
    frame.gnss_sigma_m = fix->sigma_m;
  }
  return true;
}

}  // namespace mapnav::detail
