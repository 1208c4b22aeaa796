#pragma once
// The routing speed scene, shared by `mapnav bench` and bench/route_bench.cpp (Google Benchmark): a
// generated grid campus (map/generate.h: intersections 40 m apart) and 32 queries between random
// road positions (seeded), so that both time the same queries.
#include <memory>
#include <utility>
#include <vector>

#include "mapnav/map/map.h"
#include "mapnav/navigator/road_position.h"

namespace mapnav {

struct RouteScene {
  std::unique_ptr<Map> map;  ///< on the heap: a RoadGraph keeps a reference to it
  std::vector<std::pair<RoadPosition, RoadPosition>> queries;
};

/// A square grid of at least `intersections` (≥ 4; rounded up to n × n) and its 32 queries. `bent`:
/// every road bent at its middle, the middle point moved up to 3 m sideways (seeded) — an irregular,
/// OpenStreetMap-like map of the same topology, as bench/osm_bench.cpp imports (224 × 224
/// intersections: 99 904 ways), on which the straight-line bound of A* is no longer the road's length.
RouteScene makeRouteScene(int intersections, bool bent = false);

}  // namespace mapnav
