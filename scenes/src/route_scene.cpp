// The routing speed scene (mapnav/scenes/route_scene.h).
#include "mapnav/scenes/route_scene.h"

#include <random>
#include <utility>

#include "mapnav/geometry/types.h"
#include "mapnav/map/generate.h"

namespace mapnav {

RouteScene makeRouteScene(int intersections, bool bent) {
  GridMapOptions options;
  int n = 2;
  while (n * n < intersections) ++n;
  options.columns = options.rows = n;
  MapData data = makeGridMap(options);
  if (bent) {
    std::mt19937 jitter_rng(27);
    std::uniform_real_distribution<double> jitter(-3.0, 3.0);
    for (Road& road : data.roads) {
      const Vec2 a = road.centerline.points().front(), b = road.centerline.points().back();
      const Vec2 d = (b - a).normalized();
      road.centerline = Polyline2({a, 0.5 * (a + b) + jitter(jitter_rng) * leftNormal(d), b});
    }
  }
  RouteScene s;
  s.map = std::make_unique<Map>(std::move(data));
  std::mt19937 rng(3);
  std::uniform_int_distribution<std::size_t> pick(0, s.map->roads().size() - 1);
  std::uniform_real_distribution<double> along(1.0, 39.0);
  for (int i = 0; i < 32; ++i) {
    const Road& a = s.map->roads()[pick(rng)];
    const Road& b = s.map->roads()[pick(rng)];
    s.queries.emplace_back(RoadPosition{a.id, a.from, along(rng)}, RoadPosition{b.id, b.from, along(rng)});
  }
  return s;
}

}  // namespace mapnav
