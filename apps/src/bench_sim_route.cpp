#include "bench_sim_route.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <numeric>

#include "mapnav/mission/metrics.h"
#include "mapnav/mission/mission_file.h"
#include "mapnav/mission_sim/closed_loop.h"
#include "mapnav/navigator/route.h"
#include "mapnav/sim/world.h"
#include "mapnav/vision/pipelines.h"

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

double RouteTimes::meanMs() const {
  return query_ms.empty() ? 0 : std::accumulate(query_ms.begin(), query_ms.end(), 0.0) / static_cast<double>(query_ms.size());
}
double RouteTimes::medianMs() const { return percentile(query_ms, 50); }  // as the loop's latency median
double RouteTimes::maxMs() const { return percentile(query_ms, 100); }

std::vector<RouteTimes> timeRoutes(const std::vector<int>& intersections, double min_time_s, bool bent) {
  std::vector<RouteTimes> out;
  for (const int wanted : intersections) {
    const RouteScene scene = makeRouteScene(wanted, bent);
    const Map& map = *scene.map;
    const auto& queries = scene.queries;
    RouteTimes t;
    t.bent = bent;
    t.intersections = static_cast<int>(map.intersections().size());
    t.roads = static_cast<int>(map.roads().size());
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
    for (const auto& [from, to] : queries) {
      double best = 1e300;
      for (int k = 0; k < 3; ++k) {
        const Clock::time_point q0 = Clock::now();
        keep(graph.route(from, to));
        best = std::min(best, 1e3 * secondsSince(q0));
      }
      t.query_ms.push_back(best);
    }
    out.push_back(t);
  }
  return out;
}

LoopTimes timeLoop(const std::string& mission_file, std::size_t frames) {
  registerBuiltinPipelines();
  const MissionFile mission = loadMission(mission_file);
  RunOptions options;
  options.max_frames = frames;
  const MissionRun run = runClosedLoop(mission, options);
  LoopTimes t;
  t.mission = mission.name;
  t.frames = run.frames.size();
  t.median_ms = run.metrics.latency_ms_median;
  t.p99_ms = run.metrics.latency_ms_p99;
  t.vision_median_ms = run.metrics.vision_ms_median;
  return t;
}

}  // namespace mapnav::cli
