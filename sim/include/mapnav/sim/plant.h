#pragma once
// The simulated plant of a closed-loop run: what the vehicle's camera sees at a pose and time (a
// frame rendered from the synthetic world, sim/world.h) and what its odometry reports for a true
// motion (the noisy sensor, logs/odometry.h). Poses are world frame (x, y in m, heading in rad);
// motions are per interval in the vehicle frame (geometry/motion.h); times in seconds.
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/motion.h"
#include "mapnav/geometry/pose2.h"
#include <optional>

#include "mapnav/logs/gnss.h"
#include "mapnav/logs/odometry.h"
#include "mapnav/map/map.h"
#include "mapnav/sim/map_error.h"
#include "mapnav/sim/world.h"

namespace mapnav {

/// The synthetic world and the odometry noise of a simulation (a mission's `world` and `odometry`
/// objects, their seeds included), and how the world differs from the map (`world.map_error`).
struct PlantOptions {
  WorldOptions world;
  OdometryNoiseOptions odometry;
  MapErrorOptions map_error;
  /// The vehicle's GNSS receiver (the world's `gnss`): a fix with every frame; none: no receiver.
  std::optional<GnssReceiverOptions> gnss;
};

class SimulatedPlant {
 public:
  /// The world of `map` (copied: the map need not outlive the plant), perturbed by
  /// options.map_error (map_error.h), seen through `camera` (its ray table built once). Throws
  /// InvalidInput for invalid options, ValidationError when the perturbed map is invalid.
  SimulatedPlant(const Map& map, const Camera& camera, const PlantOptions& options);

  /// The map the world is drawn from: the plant's map perturbed (the map itself when
  /// options.map_error.none()). Truth is judged against it: its roads are where the vehicle can drive.
  const Map& worldMap() const { return world_map_; }

  /// The camera frame at `pose` (world frame) at mission time `t` s, with its ground-truth mask.
  Frame render(const Pose2& pose, double t) const;
  /// What the odometry sensor reports for the true motion `truth` over `dt_s` s (the noise's random
  /// stream advances: the same calls in the same order give the same readings).
  MotionIncrement odometry(const MotionIncrement& truth, double dt_s);
  /// The receiver's fix at the true position `truth` (world frame) at time `t` (not decreasing from
  /// call to call); none without a receiver.
  std::optional<GnssFix> gnss(const Vec2& truth, double t);

 private:
  Map world_map_;
  World world_;
  RayTable rays_;
  OdometrySensor sensor_;
  std::optional<GnssReceiver> receiver_;
};

}  // namespace mapnav
