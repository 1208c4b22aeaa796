#pragma once
// What `simulate()` and the closed loop share (internal to mission_sim/): the simulated plant's
// settings from the mission's `world` and `odometry` blocks, the wander path, and the loop that steps
// the vehicle between camera frames. simulate() steers it with pure pursuit on the TRUE pose; the
// closed loop with Motion Control on the ESTIMATED pose. Both get the same frame timing and true
// motion between frames (vehicle frame, m and rad; times in s). The route through the mission's
// stops is mission/'s (mission/mission_route.h).
#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <vector>

#include "mapnav/geometry/motion.h"
#include "mapnav/geometry/polyline2.h"
#include "mapnav/mission/mission_file.h"
#include "mapnav/navigator/path.h"
#include "mapnav/navigator/vehicle.h"
#include "mapnav/sim/plant.h"

namespace mapnav::detail {

/// The synthetic world (its map error and GNSS receiver too) and odometry noise of a mission's `world`
/// and `odometry` objects, `seed` overriding the world's seed, the odometry's (seed + 1), the map
/// error's (seed + 2) and the receiver's (seed + 3): same seed, same bytes; the world's map loaded.
/// Throws ValidationError naming the mission and every bad field, or the world's map when it is not
/// valid or lacks a road of `map` (requireSameRoads).
PlantOptions simulationSettings(const MissionFile& mission, const Map& map, const std::optional<std::uint64_t>& seed);

/// The path the simulator's driver follows: the route with a gentle lateral wander (a sine of
/// `amplitude` metres and a 25 m wavelength, faded in and out over the first and last 5 m).
std::vector<PathPoint> wanderPath(const Polyline2& route, double amplitude);

struct DriveLoopOptions {
  double frame_dt_s = 0.5;    ///< between camera frames, s
  double control_dt_s = 0.05; ///< between control steps, s
  double time_limit_s = 1e9;  ///< no control step after this time, s
  std::size_t max_frames = 0; ///< stop after this many frames (0: no limit)
};

struct DriveLoopResult {
  std::size_t frames = 0;
  double distance_m = 0;  ///< driven (true)
  double duration_s = 0;  ///< mission time at the end
  bool finished = false;  ///< `finished()` said so (not a limit, not `on_frame`)
};

/// The vehicle between camera frames: the frame clock (frames due at t = 0, frame_dt, 2 frame_dt, ...)
/// and the control steps in between, summing the true motion since the last frame.
class Drive {
 public:
  enum class Stop { Frame, Finished, TimeLimit };
  struct Step {
    Stop stop = Stop::Frame;
    MotionIncrement motion;  ///< Frame: the true motion since the previous frame (none for the first)
    double dt_s = 0;         ///< Frame: the time since the previous frame (0 for the first)
  };

  /// `vehicle` is stepped in place; options.max_frames is the caller's to check (frames()).
  Drive(SkidSteerVehicle& vehicle, const DriveLoopOptions& options);

  /// Steps the vehicle control_dt_s at a time with `command(t)` until a frame is due, and takes it
  /// (Frame; the first is due at once, and each later one after at least one step). Before each
  /// step `finished()` is asked (true: Finished), then the time limit (past it: TimeLimit).
  Step toNextFrame(const std::function<VehicleCommand(double)>& command, const std::function<bool()>& finished);

  double t() const { return t_; }                    ///< mission time, s
  double distance_m() const { return distance_m_; }  ///< driven (true), m
  std::size_t frames() const { return frames_; }     ///< frames taken

 private:
  SkidSteerVehicle& vehicle_;
  DriveLoopOptions options_;
  double t_ = 0, next_frame_ = 0, last_frame_t_ = 0;
  double distance_m_ = 0;
  std::size_t frames_ = 0;
  MotionIncrement motion_;  // the true motion since the last frame
  bool stepped_ = true;     // a step since the last frame taken (none is needed before the first)
};

/// The loop: at t = 0, frame_dt, 2 frame_dt, ... `on_frame(t, vehicle pose, true motion since the
/// last frame, time since the last frame (0 for the first))` (false: stop); between frames `finished()` is asked (true: stop), then the vehicle steps
/// `control_dt_s` with `command(t)`.
DriveLoopResult driveLoop(SkidSteerVehicle& vehicle, const DriveLoopOptions& options,
                          const std::function<bool(double, const Pose2&, const MotionIncrement&, double)>& on_frame,
                          const std::function<VehicleCommand(double)>& command,
                          const std::function<bool()>& finished);

}  // namespace mapnav::detail
