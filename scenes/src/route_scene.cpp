// The routing speed scene (mapnav/scenes/route_scene.h).
#include "mapnav/scenes/route_scene.h"

#include <random>

#include "mapnav/map/generate.h"

namespace mapnav {

RouteScene makeRouteScene(int intersections) {
  GridMapOptions options;
  int n = 2;
  while (n * n < intersections) ++n;
  options.columns = options.rows = n;
  RouteScene s;
  s.map = std::make_unique<Map>(makeGridMap(options));
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
