#include "bench_sim_route.h"

#include <cstdint>
#include <cstring>

#include "mapnav/navigator/route.h"
#include "mapnav/sim/world.h"

namespace mapnav::cli {

RenderTimes timeRender(const SidewalkScene& scene, double min_time_s) {
  RenderTimes t;
  t.width = scene.camera->width();
  t.height = scene.camera->height();
  const World world(scene.map, WorldOptions{});
  const RayTable rays(*scene.camera);
  std::size_t k = 0;
  t.render = measure(
      [&] {
        const std::size_t i = k++ % scene.poses.size();
        const Frame frame = world.render(rays, scene.poses[i], 0.1 * static_cast<double>(i));
        keep(frame.rgb.data.front());
      },
      min_time_s);
  const Frame& f = scene.frames.front();
  std::vector<std::uint8_t> rgb(f.rgb.data.size()), mask(f.mask.data.size());
  t.copy = measure(
      [&] {
        std::memcpy(rgb.data(), f.rgb.data.data(), rgb.size());
        std::memcpy(mask.data(), f.mask.data.data(), mask.size());
        keep(rgb.front());
        keep(mask.front());
      },
      min_time_s);
  return t;
}

std::vector<RouteTimes> timeRoutes(const std::vector<int>& intersections, double min_time_s) {
  std::vector<RouteTimes> out;
  for (const int wanted : intersections) {
    const RouteScene scene = makeRouteScene(wanted);
    const Map& map = *scene.map;
    const auto& queries = scene.queries;
    RouteTimes t;
    t.intersections = static_cast<int>(map.intersections().size());
    const Clock::time_point t0 = Clock::now();
    RoadGraph graph(map);
    keep(graph.route(queries.front().first, queries.front().second));  // the landmarks
    t.prep_s = secondsSince(t0);
    const auto timeQueries = [&](bool astar) {
      RouteOptions ro;
      ro.use_astar = astar;
      std::size_t k = 0;
      return measure(
          [&] {
            const auto& [from, to] = queries[k++ % queries.size()];
            keep(graph.route(from, to, ro));
          },
          min_time_s);
    };
    t.astar = timeQueries(true);
    t.dijkstra = timeQueries(false);
    out.push_back(t);
  }
  return out;
}

}  // namespace mapnav::cli
