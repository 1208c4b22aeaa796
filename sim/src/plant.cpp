// The simulated plant: the synthetic world rendered through a kept ray table, and the odometry sensor.
#include "mapnav/sim/plant.h"

#include "mapnav/core/error.h"
#include "mapnav/core/issue.h"

namespace mapnav {

SimulatedPlant::SimulatedPlant(const Map& map, const Camera& camera, const PlantOptions& options)
    : world_map_(perturbedMap(options.world_map ? *options.world_map : map, options.map_error,
                              "the world of map \"" + map.name() + "\"")),
      world_(world_map_, options.world), rays_(camera), sensor_(options.odometry) {
  if (options.gnss) receiver_.emplace(*options.gnss);
  if (!options.world_map && !options.map_error.none()) field_.emplace(options.map_error);
}

std::optional<Pose2> SimulatedPlant::truthOnMap(const Pose2& pose) const {
  if (!field_) return std::nullopt;
  return field_->pullBack(pose);
}

std::optional<GnssFix> SimulatedPlant::gnss(const Vec2& truth, double t) {
  if (!receiver_) return std::nullopt;
  return receiver_->measure(truth, t);
}

Frame SimulatedPlant::render(const Pose2& pose, double t) const { return world_.render(rays_, pose, t); }

MotionIncrement SimulatedPlant::odometry(const MotionIncrement& truth, double dt_s) {
  return sensor_.measure(truth.distance_m, truth.dheading_rad, dt_s);
}

void requireSameRoads(const Map& map, const Map& world, const std::string& world_source) {
  Issues issues;
  for (const Intersection& i : map.intersections()) {
    if (!world.findIntersection(i.id)) {
      addIssue(issues, Severity::Error, "world.same_roads", "/intersections",
               "intersection \"" + i.id + "\" of map \"" + map.name() + "\" is not in the world's map");
    }
  }
  for (const Road& r : map.roads()) {
    const Road* w = world.findRoad(r.id);
    if (!w) {
      addIssue(issues, Severity::Error, "world.same_roads", "/roads",
               "road \"" + r.id + "\" of map \"" + map.name() + "\" is not in the world's map");
    } else if (w->from != r.from || w->to != r.to) {
      addIssue(issues, Severity::Error, "world.same_roads", "/roads",
               "road \"" + r.id + "\" runs " + w->from + " -> " + w->to + " in the world's map but " + r.from + " -> " +
                   r.to + " in map \"" + map.name() + "\"");
    }
  }
  if (hasErrors(issues)) throw ValidationError(world_source, std::move(issues));
}

}  // namespace mapnav
