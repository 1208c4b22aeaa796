#pragma once
// Where the runner's camera frames come from: a FrameSource yields them one at a time — a recorded
// log (the replay source, internal to mission/) or a plant the modules drive in closed loop (a
// DrivenSource: mission_sim's simulated plant, mission_sim/closed_loop.h) — and the runner is one
// loop over it: the next frame, the four modules, and, for a plant, Motion Control driving it to the
// next frame (the Driver). Poses are world frame (x, y in m, heading in rad), motions per interval in
// the vehicle frame (geometry/motion.h), times mission time in seconds.
//
// mission/ holds the interface and the closed loop's runner over any DrivenSource
// (runClosedLoopOver), not a plant: so that the replay of a log links no renderer.
#include <cstddef>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/motion.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/image/image.h"
#include "mapnav/map/map.h"
#include "mapnav/mission/mission_file.h"
#include "mapnav/mission/runner.h"
#include "mapnav/navigator/vehicle.h"

namespace mapnav {

/// One camera frame as the modules take it.
struct SourceFrame {
  std::size_t index = 0;         ///< replay: the log's frame index (frames skipped count); closed loop: frames before
  double t = 0;                  ///< mission time, s
  Image rgb;                     ///< 3 channels, the camera's size
  MotionIncrement odometry;      ///< measured since the previous frame delivered (the first: since the start)
  std::optional<Pose2> truth;    ///< the vehicle's true pose (world frame), when the source knows it
  std::optional<Pose2> truth_on_map;  ///< where that pose is on the vehicle's map, when the world differs from it (SimulatedPlant::truthOnMap)
  std::optional<Vec2> gnss;      ///< the log's (closed loop: the plant's) GNSS fix with this frame (world frame, m) ...
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

/// A source that carries a vehicle the modules drive between frames (a closed loop's plant): what
/// the runner asks it once the frames are done, for the run's distance, time and outcome.
class DrivenSource : public FrameSource {
 public:
  /// Where the vehicle truly is (world frame).
  virtual const Pose2& pose() const = 0;
  /// The driver said it arrived (not a limit, not the modules).
  virtual bool finished() const = 0;
  /// Frames delivered.
  virtual std::size_t frames() const = 0;
  /// Driven (true), m.
  virtual double distance_m() const = 0;
  /// Mission time at the end, s.
  virtual double duration_s() const = 0;
  /// The mission time after which the vehicle is no longer driven, s (the outcome names it).
  virtual double time_limit_s() const = 0;
};

/// Makes a closed loop's source once the route is planned: `run` holds the mission's route, start
/// and goal (world frame), `limits` the vehicle's (fast enough for the mission's speed).
using DrivenSourceFactory = std::function<std::unique_ptr<DrivenSource>(const MissionRun& run, const VehicleLimits& limits)>;

/// The closed loop over the source `make_source` makes (mission_sim's runClosedLoop: the simulated
/// plant): the four modules once a frame, Motion Control driving the source's vehicle between frames;
/// mode "closed-loop", the truth the source's. `camera` took the source's frames; `map` and `camera`
/// are used during the call only. `world`: the map the source's world is drawn from when it is not
/// `map` (a world that differs from its map, sim/map_error.h): the truth is judged against it (on
/// the path, how far the vehicle ends from the goal's road position on the world's roads); the
/// source's vehicle should start at the mission's start on them. Throws as runReplay.
MissionRun runClosedLoopOver(const MissionFile& mission, const Map& map, const Camera& camera,
                             const RunOptions& options, const DrivenSourceFactory& make_source,
                             const Map* world = nullptr);

}  // namespace mapnav
