// Route queries on generated grid campuses of 10k and 100k intersections (100 × 100 and
// 316 × 316, 40 m apart): milliseconds per query between random road positions (seeded). The
// graph is built once per map; a query only adds and removes its start and goal edges.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <random>

#include "mapnav/map/generate.h"
#include "mapnav/navigator/route.h"

namespace {

using namespace mapnav;

struct Campus {
  std::unique_ptr<Map> map;
  std::unique_ptr<RoadGraph> graph;
  std::vector<std::pair<RoadPosition, RoadPosition>> queries;
};

Campus& campus(int intersections) {
  static std::map<int, Campus> campuses;
  auto it = campuses.find(intersections);
  if (it != campuses.end()) return it->second;
  GridMapOptions options;
  int n = 2;
  while (n * n < intersections) ++n;
  options.columns = options.rows = n;
  Campus c;
  c.map = std::make_unique<Map>(makeGridMap(options));
  c.graph = std::make_unique<RoadGraph>(*c.map);
  std::mt19937 rng(3);
  std::uniform_int_distribution<std::size_t> pick(0, c.map->roads().size() - 1);
  std::uniform_real_distribution<double> along(1.0, 39.0);
  for (int i = 0; i < 32; ++i) {
    const Road& a = c.map->roads()[pick(rng)];
    const Road& b = c.map->roads()[pick(rng)];
    c.queries.emplace_back(RoadPosition{a.id, a.from, along(rng)}, RoadPosition{b.id, b.from, along(rng)});
  }
  return campuses.emplace(intersections, std::move(c)).first->second;
}

void BM_RouteQuery(benchmark::State& state) {
  Campus& c = campus(static_cast<int>(state.range(0)));
  RouteOptions options;
  options.use_astar = state.range(1) != 0;
  std::size_t i = 0;
  double length = 0;
  for (auto _ : state) {
    const auto& [from, to] = c.queries[i++ % c.queries.size()];
    const RouteResult r = c.graph->route(from, to, options);
    length += r.route ? r.route->length_m : 0;
    benchmark::DoNotOptimize(r);
  }
  state.counters["intersections"] = static_cast<double>(c.map->intersections().size());
  state.counters["route_m"] = length / static_cast<double>(state.iterations());
  state.SetLabel(options.use_astar ? "A*" : "Dijkstra");
}
// Args: intersections, A* (1) or Dijkstra (0).
BENCHMARK(BM_RouteQuery)->Args({10000, 1})->Args({100000, 1})->Args({10000, 0})->Unit(benchmark::kMillisecond);

}  // namespace
