#pragma once
// `mapnav bench`'s other two measurements: the simulator's renderer per frame beside a
// memcpy of the frame, and route queries on generated grid campuses, A* beside the Dijkstra
// reference, with their growth from 10k to 100k intersections (internal to apps/).
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
  int intersections = 0;
  double prep_s = 0;
  Measured astar, dijkstra;  // per query
  double dijkstraRatio() const { return dijkstra.s_per_frame / astar.s_per_frame; }
};
/// Grid campuses of `intersections` each (rounded up to a square), in that order.
std::vector<RouteTimes> timeRoutes(const std::vector<int>& intersections, double min_time_s);

}  // namespace mapnav::cli
