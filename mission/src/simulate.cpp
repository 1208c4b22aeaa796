#include "mapnav/mission/simulate.h"

#include <cmath>

#include "mapnav/core/error.h"
#include "mapnav/core/options.h"
#include "mapnav/map/camera_io.h"
#include "mapnav/map/map_io.h"
#include "mapnav/navigator/path.h"
#include "mapnav/navigator/route.h"
#include "mapnav/navigator/steering.h"
#include "mapnav/navigator/vehicle.h"
#include "mapnav/sim/odometry.h"
#include "mapnav/sim/replay_log.h"
#include "mapnav/sim/world_io.h"

namespace mapnav {

void SimulateOptions::validate() const {
  requireOption(std::isfinite(control_dt_s) && control_dt_s > 0 && control_dt_s <= 0.5, "SimulateOptions",
                "control_dt_s", control_dt_s, "in (0, 0.5]");
}

namespace {

// The route through every via point, as one centre line, with the intersections it passes.
Polyline2 plan(const Map& map, const MissionFile& mission, SimulateResult& result) {
  RoadGraph graph(map);
  std::vector<RoadPosition> stops{mission.start};
  stops.insert(stops.end(), mission.via.begin(), mission.via.end());
  stops.push_back(mission.goal);
  std::vector<Vec2> line;
  for (std::size_t i = 0; i + 1 < stops.size(); ++i) {
    const RouteResult leg = graph.route(stops[i], stops[i + 1]);
    if (!leg.route) throw Unreachable("mission \"" + mission.name + "\": no route: " + leg.reason);
    for (const Vec2& p : leg.route->line.points()) {
      if (line.empty() || (line.back() - p).norm() > 1e-9) line.push_back(p);
    }
    result.intersections.insert(result.intersections.end(), leg.route->intersections.begin(),
                                leg.route->intersections.end());
  }
  return Polyline2(std::move(line));
}

// The path the controller follows: the route with a gentle lateral wander (a sine of `amplitude`
// metres and a 25 m wavelength, faded in and out over the first and last 5 m).
std::vector<PathPoint> wander(const Polyline2& route, double amplitude) {
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

}  // namespace

SimulateResult simulate(const MissionFile& mission, const std::filesystem::path& log_dir, const SimulateOptions& options) {
  options.validate();
  const Map map = loadMap(mission.map);
  const std::shared_ptr<const Camera> camera = loadCamera(mission.camera);
  Issues issues;
  WorldOptions world_options = parseWorldOptions(mission.world_json, "/world", issues);
  OdometryNoiseOptions odometry_options = parseOdometryNoise(mission.odometry_json, "/odometry", issues);
  if (hasErrors(issues)) throw ValidationError(mission.name, std::move(issues));
  if (options.seed) {
    world_options.seed = *options.seed;
    odometry_options.seed = *options.seed + 1;
  }

  SimulateResult result;
  const Polyline2 route = plan(map, mission, result);
  result.route_length_m = route.length();
  const std::vector<PathPoint> path = wander(route, mission.wander_m);
  VehicleLimits limits;
  limits.max_speed_mps = std::max(limits.max_speed_mps, mission.speed_mps);
  SkidSteerVehicle vehicle(Pose2(path.front().position, path.front().heading), limits);
  PurePursuitOptions follow;
  follow.speed_mps = mission.speed_mps;
  PurePursuit controller(path, follow, limits);
  const World world(map, world_options);
  OdometrySensor odometry(odometry_options);

  LogHeader header;
  header.name = mission.name;
  header.camera = camera;
  std::error_code ec;
  const auto map_abs = std::filesystem::weakly_canonical(mission.map, ec);
  header.map = map_abs.string();
  header.frame_rate_hz = mission.frame_rate_hz;
  ReplayLogWriter writer(log_dir, std::move(header));

  const double frame_dt = 1.0 / mission.frame_rate_hz;
  const double time_limit = 3.0 * route.length() / mission.speed_mps + 60.0;
  double t = 0, next_frame = 0, last_frame_t = 0, distance = 0, dheading = 0;
  while (true) {
    if (t >= next_frame - 1e-9) {
      const Pose2& pose = vehicle.pose();
      const Frame frame = world.render(*camera, pose, t);
      LogFrame entry;
      entry.t = t;
      entry.odometry = odometry.measure(distance, dheading, t - last_frame_t);
      entry.truth = pose;
      writer.add(entry, frame.rgb, &frame.mask);
      distance = dheading = 0;
      last_frame_t = t;
      next_frame += frame_dt;
      ++result.frames;
      if (options.max_frames > 0 && result.frames >= options.max_frames) break;
    }
    if (controller.finished(vehicle.pose())) {
      result.reached_goal = true;
      break;
    }
    if (t > time_limit) break;
    const Pose2 before = vehicle.pose();
    vehicle.step(controller.command(before), options.control_dt_s);
    const double step = (vehicle.pose().translation() - before.translation()).norm();
    distance += step;
    result.distance_m += step;
    dheading += normalizeAngle(vehicle.pose().heading() - before.heading());
    t += options.control_dt_s;
  }
  result.duration_s = t;
  writer.finish();
  return result;
}

}  // namespace mapnav
