// The sidewalk speed scene (mapnav/scenes/sidewalk_scene.h).
#include "mapnav/scenes/sidewalk_scene.h"

#include <algorithm>
#include <cmath>

#include "mapnav/geometry/camera_io.h"
#include "mapnav/map/map_io.h"
#include "mapnav/map/predict.h"

namespace mapnav {

SidewalkScene makeSidewalkScene(const std::filesystem::path& maps, int frames) {
  SidewalkScene s{loadMap(maps / "cmu_campus.json"), loadCamera(maps / "cameras" / "terregator_pinhole.json"), {}, {}, {}};
  WorldOptions wo;  // campus_dialogue's world block
  wo.seed = 1985;
  wo.shadow_density = 0.05;
  wo.leaf_density = 0.02;
  wo.noise_sigma = 2.0;
  const World world(s.map, wo);
  const RayTable rays(*s.camera);
  const Polyline2& line = s.map.road("R1").centerline;
  for (int i = 0; i < std::max(1, frames); ++i) {
    const double along = 3.0 + 0.6 * i;
    const Vec2 t = line.tangentAt(along);
    const Pose2 pose(line.pointAt(along), std::atan2(t.y(), t.x()));
    s.poses.push_back(pose);
    s.frames.push_back(world.render(rays, pose, 0.5 * i));
    s.predictions.push_back(predictView(s.map, pose, *s.camera).view);
  }
  return s;
}

}  // namespace mapnav
