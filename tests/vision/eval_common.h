#pragma once
// Shared helpers of the vision tests: the campus and park maps, the pin-hole camera, poses along roads.
#include <cmath>
#include <memory>
#include <numbers>
#include <vector>

#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/map/map.h"
#include "mapnav/map/map_io.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav::visiontest {

/// The campus without its landmarks (testing::withoutLandmarks).
inline const Map& campus() { return testing::campusWithoutLandmarks(); }

inline const Map& park() {
  static const Map map = loadMap(testing::mapPath("park_path.json"));
  return map;
}

inline const Camera& pinhole() {
  static const std::unique_ptr<Camera> cam =
      loadCamera(testing::sourceDir() / "maps" / "cameras" / "terregator_pinhole.json");
  return *cam;
}

/// Poses along every road's centre line, every `step` m (starting 1 m in), alternating direction,
/// with small lateral (±0.3 m) and heading (±5°) offsets, in a fixed pattern.
inline std::vector<Pose2> roadPoses(const Map& map, double step) {
  std::vector<Pose2> poses;
  int k = 0;
  const double lateral[] = {0.0, 0.25, -0.3, 0.1, -0.15};
  const double dheading[] = {0.0, -4.0, 3.0, 5.0, -2.0};
  for (const Road& road : map.roads()) {
    const Polyline2& line = road.centerline;
    for (double s = 1.0; s < line.length() - 1.0; s += step, ++k) {
      const bool reverse = (k % 2) == 1;
      const Vec2 p = line.pointAt(s);
      const Vec2 t = line.tangentAt(s);
      const Vec2 left(-t.y(), t.x());
      double heading = std::atan2(t.y(), t.x()) + (reverse ? std::numbers::pi : 0.0);
      heading += dheading[k % 5] * std::numbers::pi / 180.0;
      poses.emplace_back(p + lateral[k % 5] * left, heading);
    }
  }
  return poses;
}

}  // namespace mapnav::visiontest
