#include "bench_sim_route.h"

#include <cmath>
#include <cstdint>
#include <cstring>

#include "mapnav/navigator/route.h"
#include "mapnav/sim/world.h"

namespace mapnav::cli {

RenderTimes timeRender(const SidewalkScene& scene, double min_time_s) {
  RenderTimes t;
  t.width = scene.camera->width();
  t.height = scene.camera->height();
  const RayTable rays(*scene.camera);
  // A drive of 0.1 m a frame from the scene's first pose along its heading, from an empty texel
  // cache: each frame sees ground ahead that the frames before did not, as a mission's frames do.
  const auto drive = [&](const WorldOptions& options) {
    const World world(scene.map, options);
    const Pose2 start = scene.poses.front();
    const Vec2 ahead(std::cos(start.heading()), std::sin(start.heading()));
    std::size_t k = 0;
    return measure(
        [&] {
          const double s = 0.1 * static_cast<double>(k++);
          const Frame frame = world.render(rays, Pose2(start.translation() + s * ahead, start.heading()), s);
          keep(frame.rgb.data.front());
        },
        min_time_s);
  };
  WorldOptions texels;
  texels.texel_cache_mib = 64;
  t.render = drive(texels);
  t.per_pixel = drive(WorldOptions{});
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
