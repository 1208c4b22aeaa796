// The simulated plant: the synthetic world rendered through a kept ray table, and the odometry sensor.
#include "mapnav/sim/plant.h"

namespace mapnav {

SimulatedPlant::SimulatedPlant(const Map& map, const Camera& camera, const PlantOptions& options)
    : world_map_(perturbedMap(map, options.map_error, "the world of map \"" + map.name() + "\"")),
      world_(world_map_, options.world), rays_(camera), sensor_(options.odometry) {
  if (options.gnss) receiver_.emplace(*options.gnss);
}

std::optional<GnssFix> SimulatedPlant::gnss(const Vec2& truth, double t) {
  if (!receiver_) return std::nullopt;
  return receiver_->measure(truth, t);
}

Frame SimulatedPlant::render(const Pose2& pose, double t) const { return world_.render(rays_, pose, t); }

MotionIncrement SimulatedPlant::odometry(const MotionIncrement& truth, double dt_s) {
  return sensor_.measure(truth.distance_m, truth.dheading_rad, dt_s);
}

}  // namespace mapnav
