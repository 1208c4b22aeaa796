#pragma once
// `mapnav bench`: the speed of the park-mode road finder's runtime (Jochem & Baluja 1993, §6) on the
// scene of mapnav/scenes/park_scene.h, per colour frame, single-threaded and on every core, with its
// ratios to a memcpy of the same frame and to the per-pixel reference path; and the training time;
// then the default Vision pipeline ("sidewalk") per frame at 512 x 480 with the same two ratios.
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/vision/cluster_perceptron.h"

namespace mapnav::cli {

struct BenchConfig {
  std::vector<int> sizes{64, 128, 256, 512, 1024};  ///< square frames, pixels a side, 16..4096
  double min_time_s = 0.2;  ///< at least this long per measured cell (batches until then)
  int threads = 0;          ///< the multi-threaded rows: this many threads, 0 = every core
  std::string map;          ///< the park map; empty = defaultParkMapPath()
  bool json = false;        ///< one JSON object on stdout instead of the table
  /// The road finder's model (--road-model): the paper's straight line (default) or the §9 arc, whose
  /// ground refinement is timed too.
  RoadModel road_model = RoadModel::Line;
  /// The grid campuses of the route queries, intersections each (rounded up to a square grid),
  /// 4..4 000 000; empty = no route queries.
  std::vector<int> route_sizes{10000, 100000};
  /// The same on the irregular, OpenStreetMap-like maps (every road bent at its middle:
  /// makeRouteScene's `bent`); 50 176 intersections are 99 904 ways. Empty = none.
  std::vector<int> irregular_route_sizes{50000};
  /// The mission loop's latency: a closed loop of maps/missions/campus_dialogue.json for this many
  /// frames (0 = not measured).
  std::size_t loop_frames = 80;
  /// The vision pipelines timed per frame (--pipelines): every registered one by default, none when
  /// empty.
  std::optional<std::vector<std::string>> pipelines;
};

/// maps/park_path.json: the installed copy next to the program (../share/mapnav/maps) when there is
/// one, else the source tree's. The sidewalk scene's map and camera come from the same folder.
std::string defaultParkMapPath();

/// "64,128,256": the sizes, each a whole number in [16, 4096], sorted, without repeats. Throws
/// InvalidInput naming --sizes.
std::vector<int> parseBenchSizes(const std::string& text);
/// "10000,100000": intersections, whole numbers in [4, 4000000], sorted, without repeats; "" = none.
/// Throws InvalidInput naming `flag`.
std::vector<int> parseRouteSizes(const std::string& text, const std::string& flag = "--route-sizes");
/// "0.2": seconds, a number in (0, 60]. Throws InvalidInput naming --min-time.
double parseBenchMinTime(const std::string& text);

/// The threads a `threads` option means: itself, or every core for 0 (at least 1).
int resolveThreads(int threads);

int runBench(const BenchConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
