#include "drive.h"

#include <algorithm>
#include <cmath>

#include "mapnav/core/error.h"
#include "mapnav/core/interrupt.h"
#include "mapnav/logs/odometry.h"
#include "mapnav/map/map_io.h"
#include "mapnav/sim/world_io.h"

namespace mapnav::detail {

PlantOptions simulationSettings(const MissionFile& mission, const Map& map, const std::optional<std::uint64_t>& seed) {
  Issues issues;
  PlantOptions s{parseWorldOptions(mission.world_json, "/world", issues),
                 parseOdometryNoise(mission.odometry_json, "/odometry", issues),
                 parseMapErrorOptions(mission.world_json, "/world", issues),
                 parseGnssOptions(mission.world_json, "/world", issues),
                 nullptr};
  if (hasErrors(issues)) throw ValidationError(mission.file.empty() ? mission.name : mission.file.string(), std::move(issues));
  if (!mission.world_map.empty()) {
    s.world_map = std::make_shared<const Map>(loadMap(mission.world_map));
    requireSameRoads(map, *s.world_map, mission.world_map.string());
  }
  if (seed) {
    s.world.seed = *seed;
    s.odometry.seed = *seed + 1;
    s.map_error.seed = *seed + 2;
    if (s.gnss) s.gnss->seed = *seed + 3;
  }
  return s;
}

std::vector<PathPoint> wanderPath(const Polyline2& route, double amplitude) {
  const std::vector<PathPoint> dense = densePath(route, 0.25);
  if (amplitude <= 0) return dense;
  const double length = route.length();
  std::vector<Vec2> shifted;
  for (const PathPoint& p : dense) {
    const double fade = std::min({1.0, p.s / 5.0, (length - p.s) / 5.0});
    const double offset = amplitude * fade * std::sin(2 * kPi * p.s / 25.0);
    shifted.push_back(p.position + offset * leftNormal(unitVector(p.heading)));
  }
  return densePath(Polyline2(std::move(shifted)), 0.25);
}

Drive::Drive(SkidSteerVehicle& vehicle, const DriveLoopOptions& options) : vehicle_(vehicle), options_(options) {}

Drive::Step Drive::toNextFrame(const std::function<VehicleCommand(double)>& command,
                               const std::function<bool()>& finished) {
  while (true) {
    if (stepped_) {
      throwIfInterrupted();  // Ctrl-C: unwind, so that the log writer removes its temporary folder
      if (t_ >= next_frame_ - 1e-9) {
        const Step frame{Stop::Frame, motion_, t_ - last_frame_t_};
        motion_ = MotionIncrement{};
        last_frame_t_ = t_;
        next_frame_ += options_.frame_dt_s;
        ++frames_;
        stepped_ = false;
        return frame;
      }
    }
    if (finished()) return Step{Stop::Finished, {}, 0};
    if (t_ > options_.time_limit_s) return Step{Stop::TimeLimit, {}, 0};
    const Pose2 before = vehicle_.pose();
    vehicle_.step(command(t_), options_.control_dt_s);
    const double step = (vehicle_.pose().translation() - before.translation()).norm();
    motion_.distance_m += step;
    distance_m_ += step;
    motion_.dheading_rad += normalizeAngle(vehicle_.pose().heading() - before.heading());
    t_ += options_.control_dt_s;
    stepped_ = true;
  }
}

DriveLoopResult driveLoop(SkidSteerVehicle& vehicle, const DriveLoopOptions& options,
                          const std::function<bool(double, const Pose2&, const MotionIncrement&, double)>& on_frame,
                          const std::function<VehicleCommand(double)>& command,
                          const std::function<bool()>& finished) {
  Drive drive(vehicle, options);
  DriveLoopResult result;
  while (true) {
    const Drive::Step step = drive.toNextFrame(command, finished);
    if (step.stop != Drive::Stop::Frame) {
      result.finished = step.stop == Drive::Stop::Finished;
      break;
    }
    if (!on_frame(drive.t(), vehicle.pose(), step.motion, step.dt_s)) break;
    if (options.max_frames > 0 && drive.frames() >= options.max_frames) break;
  }
  result.frames = drive.frames();
  result.distance_m = drive.distance_m();
  result.duration_s = drive.t();
  return result;
}

}  // namespace mapnav::detail
