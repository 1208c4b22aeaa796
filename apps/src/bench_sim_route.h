#pragma once
// `mapnav bench`'s other measurements: the simulator's renderer per frame beside a memcpy of the
// frame, route queries on generated grid campuses (straight and bent), A* beside the Dijkstra
// reference, with their growth from 10k to 100k intersections, and the mission loop's latency
// (internal to apps/).
#include <cstddef>
#include <string>
#include <vector>

#include "bench_measure.h"
#include "mapnav/scenes/route_scene.h"
#include "mapnav/scenes/sidewalk_scene.h"

namespace mapnav::cli {

/// World::render per frame on the sidewalk scene's map and camera (512 x 480, one thread), on a drive
/// of 0.1 m a frame from the scene's first pose: with the texel cache (WorldOptions::texel_cache_mib
/// 64) and per pixel (the default world), beside a copy of a frame's colour and mask planes.
struct RenderTimes {
  int width = 0, height = 0;
  Measured render, per_pixel, copy;
  double ms() const { return 1e3 * render.s_per_frame; }
  double memcpyRatio() const { return render.s_per_frame / copy.s_per_frame; }
  double perPixelRatio() const { return per_pixel.s_per_frame / render.s_per_frame; }
};
RenderTimes timeRender(const SidewalkScene& scene, double min_time_s);

/// One grid campus (mapnav/scenes/route_scene.h): its size, the preprocessing (RoadGraph and the
/// landmarks of the first A* query) and the mean query time over its 32 queries, with the default
/// turn penalties, by A* and by the Dijkstra reference.
struct RouteTimes {
  int intersections = 0, roads = 0;
  bool bent = false;  ///< the irregular map (makeRouteScene's `bent`)
  double prep_s = 0;
  Measured astar, dijkstra;  // per query
  std::vector<double> query_ms;  ///< each query's A* time, the best of three, ms
  double dijkstraRatio() const { return dijkstra.s_per_frame / astar.s_per_frame; }
  double meanMs() const;
  double medianMs() const;
  double maxMs() const;
};
/// Grid campuses of `intersections` each (rounded up to a square), straight or `bent`, in that order.
std::vector<RouteTimes> timeRoutes(const std::vector<int>& intersections, double min_time_s, bool bent = false);

/// The mission loop's latency (the modules per frame, the renderer not included): a closed loop of
/// `mission` for `frames` frames at its defaults, its median and 99th percentile and Vision's median.
struct LoopTimes {
  std::string mission;
  std::size_t frames = 0;
  double median_ms = 0, p99_ms = 0, vision_median_ms = 0;
};
LoopTimes timeLoop(const std::string& mission_file, std::size_t frames);

}  // namespace mapnav::cli
