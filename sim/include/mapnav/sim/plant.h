#pragma once
// The simulated plant of a closed-loop run: what the vehicle's camera sees at a pose and time (a
// frame rendered from the synthetic world, sim/world.h) and what its odometry reports for a true
// motion (the noisy sensor, logs/odometry.h). Poses are world frame (x, y in m, heading in rad);
// motions are per interval in the vehicle frame (geometry/motion.h); times in seconds.
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/motion.h"
#include "mapnav/geometry/pose2.h"
#include <memory>
#include <optional>
#include <string>

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
  /// The map the world is drawn from instead of the vehicle's (the world's `map`: a map that is
  /// wrong somewhere); map_error then perturbs it. Null (the default): the vehicle's map.
  std::shared_ptr<const Map> world_map;

  /// The world is the vehicle's map itself: no other map, no perturbation.
  bool worldIsTheMap() const { return !world_map && map_error.none(); }
};

class SimulatedPlant {
 public:
  /// The world of `map` (copied: the map need not outlive the plant), or of options.world_map,
  /// perturbed by options.map_error (map_error.h), seen through `camera` (its ray table built once).
  /// Throws InvalidInput for invalid options, ValidationError when the perturbed map is invalid. A
  /// world_map must have `map`'s roads and intersections (requireSameRoads).
  SimulatedPlant(const Map& map, const Camera& camera, const PlantOptions& options);

  /// The map the world is drawn from: the plant's map (or options.world_map) perturbed (the map
  /// itself when options.worldIsTheMap()). Truth is judged against it: its roads are where the vehicle can drive.
  const Map& worldMap() const { return world_map_; }

  /// Where the true pose `pose` (world frame) is on the vehicle's map: the pose a perfectly
  /// map-relative estimate would have (MapErrorField::pullBack) — with options.map_error over the
  /// vehicle's own map; none when the world is the map (the truth is that pose) or is drawn from
  /// another map file (no field relates the two).
  std::optional<Pose2> truthOnMap(const Pose2& pose) const;

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
  std::optional<MapErrorField> field_;  // options.map_error over the vehicle's map (truthOnMap)
  World world_;
  RayTable rays_;
  OdometrySensor sensor_;
  std::optional<GnssReceiver> receiver_;
};

/// Throws ValidationError naming `world_source` unless `world` has every intersection and road of
/// `map` by id, each road between the same intersections (road positions and the truth are read on
/// the world's roads by their ids); every difference is an issue.
void requireSameRoads(const Map& map, const Map& world, const std::string& world_source);

}  // namespace mapnav
