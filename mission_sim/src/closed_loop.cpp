// The closed loop in the simulator: the plant of the mission's world and odometry, and the runner's
// closed loop over the source that carries it (mission/frame_source.h).
#include "mapnav/mission_sim/closed_loop.h"

#include <algorithm>
#include <cstddef>
#include <memory>

#include "mapnav/geometry/camera_io.h"
#include "mapnav/geometry/types.h"
#include "mapnav/map/map_io.h"
#include "mapnav/mission/frame_source.h"
#include "mapnav/navigator/road_position.h"
#include "mapnav/sim/plant.h"

#include "closed_loop_source.h"
#include "drive.h"

namespace mapnav {

MissionRun runClosedLoop(const MissionFile& mission, const RunOptions& options) {
  options.validate();
  const Map map = loadMap(mission.map);
  const std::shared_ptr<const Camera> camera = loadCamera(mission.camera);
  const PlantOptions settings = detail::simulationSettings(mission, map, options.seed);
  SimulatedPlant plant(map, *camera, settings);
  const Map* world = settings.worldIsTheMap() ? nullptr : &plant.worldMap();
  return runClosedLoopOver(mission, map, *camera, options, [&](const MissionRun& run, const VehicleLimits& limits) {
    // The vehicle starts at the mission's start on the world's roads, turned as they are there.
    Pose2 start = run.start;
    if (world) {
      const Pose2 on_map = toPose(map, mission.start), on_world = toPose(*world, clampedTo(*world, mission.start));
      start = Pose2(on_world.translation(), run.start.heading() + normalizeAngle(on_world.heading() - on_map.heading()));
    }
    detail::DriveLoopOptions drive;
    drive.frame_dt_s = 1.0 / mission.frame_rate_hz;
    drive.control_dt_s = options.control_dt_s;
    drive.time_limit_s = 3.0 * run.route.length_m / mission.speed_mps + 60.0;
    drive.max_frames = options.max_frames;
    const std::size_t expected =
        static_cast<std::size_t>(run.route.length_m / mission.speed_mps * mission.frame_rate_hz) + 2;
    return std::make_unique<detail::ClosedLoopSource>(
        plant, start, limits, drive, options.max_frames > 0 ? std::min(options.max_frames, expected) : expected);
  }, world);
}

}  // namespace mapnav
