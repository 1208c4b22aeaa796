#include "mapnav/mission_sim/simulate.h"

#include <cmath>

#include "mapnav/core/error.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/logs/odometry.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/map/map_io.h"
#include "mapnav/mission/mission_route.h"
#include "mapnav/navigator/path.h"
#include "mapnav/navigator/progress.h"
#include "mapnav/navigator/road_position.h"
#include "mapnav/navigator/route.h"
#include "mapnav/navigator/steering.h"
#include "mapnav/navigator/vehicle.h"
#include "mapnav/sim/plant.h"

#include "drive.h"

namespace mapnav {

const OptionTable<SimulateOptions>& simulateOptionTable() {
  using O = SimulateOptions;
  static const OptionTable<O> table =
      OptionTable<O>("SimulateOptions")
          .field("max_frames", &O::max_frames, "stop after this many frames (0: drive to the goal)")
          .field("control_dt_s", &O::control_dt_s, aboveUpTo(0, 0.5),
                 "the controller's and the vehicle's time step, s");
  return table;
}

void SimulateOptions::validate() const { simulateOptionTable().validate(*this); }

SimulateResult simulate(const MissionFile& mission, const std::filesystem::path& log_dir, const SimulateOptions& options) {
  options.validate();
  const Map map = loadMap(mission.map);
  const std::shared_ptr<const Camera> camera = loadCamera(mission.camera);
  const PlantOptions settings = detail::simulationSettings(mission, map, options.seed);
  // The world the vehicle drives in: the map or the world's own (world.map), perturbed or not
  // (world.map_error); the driver follows the route on the world's roads, and the log's map stays
  // the mission's.
  SimulatedPlant plant(map, *camera, settings);
  const Map& world = plant.worldMap();

  SimulateResult result;
  RoadGraph graph(world);
  // The mission's road positions on the world's roads: the same metres from the same intersection
  // (clamped to a road the perturbation made shorter).
  std::vector<RoadPosition> stops = missionStops(mission);
  for (RoadPosition& p : stops) p = clampedTo(world, p);
  const Route planned =
      planThrough(graph, clampedTo(world, mission.start), stops, "mission \"" + mission.name + "\"");
  result.intersections = planned.intersections;
  const Polyline2& route = planned.line;
  result.route_length_m = route.length();
  VehicleLimits limits;
  limits.max_speed_mps = std::max(limits.max_speed_mps, mission.speed_mps);
  PurePursuitOptions follow;
  follow.speed_mps = mission.speed_mps;
  // The route stretch by stretch between its turnarounds (an out-and-back via point: the line comes
  // back over itself there): the driver stops at the end of one, turns around in place and follows
  // the next.
  std::vector<PurePursuit> stretches;
  double begin = 0;
  std::vector<double> ends = turnaroundArcs(planned);
  ends.push_back(route.length());
  for (const double end : ends) {
    stretches.emplace_back(detail::wanderPath(route.slice(begin, end), mission.wander_m), follow, limits);
    begin = end;
  }
  std::size_t stretch = 0;
  const PathPoint& first = stretches.front().tracker().path().front();
  SkidSteerVehicle vehicle(Pose2(first.position, first.heading), limits);
  auto finished = [&] {
    while (stretch + 1 < stretches.size() && stretches[stretch].finished(vehicle.pose())) ++stretch;
    return stretches[stretch].finished(vehicle.pose());
  };

  LogHeader header;
  header.name = mission.name;
  header.camera = camera;
  std::error_code ec;
  const auto map_abs = std::filesystem::weakly_canonical(mission.map, ec);
  header.map = map_abs.string();
  header.frame_rate_hz = mission.frame_rate_hz;
  ReplayLogWriter writer(log_dir, std::move(header));

  detail::DriveLoopOptions loop;
  loop.frame_dt_s = 1.0 / mission.frame_rate_hz;
  loop.control_dt_s = options.control_dt_s;
  loop.time_limit_s = 3.0 * route.length() / mission.speed_mps + 60.0;
  loop.max_frames = options.max_frames;
  const detail::DriveLoopResult driven = detail::driveLoop(
      vehicle, loop,
      [&](double t, const Pose2& pose, const MotionIncrement& motion, double dt_s) {
        const Frame frame = plant.render(pose, t);
        LogFrame entry;
        entry.t = t;
        entry.odometry = plant.odometry(motion, dt_s);
        entry.truth = pose;
        entry.gnss = plant.gnss(pose.translation(), t);
        writer.add(entry, frame.rgb, &frame.mask);
        return true;
      },
      [&](double) { return stretches[stretch].command(vehicle.pose()); }, finished);
  result.frames = driven.frames;
  result.distance_m = driven.distance_m;
  result.duration_s = driven.duration_s;
  result.reached_goal = driven.finished;
  writer.finish();
  return result;
}

}  // namespace mapnav
