// Route queries on generated grid campuses of 10k, 100k and 1M intersections (100 × 100, 317 × 317
// and 1000 × 1000, 40 m apart): milliseconds per query between random road positions (seeded; the
// scene mapnav/scenes/route_scene.h, which `mapnav bench` times too), with the default turn
// penalties. Each map and its RoadGraph are built once per process; the
// build and the landmark preprocessing (done by the first A* query) are timed there and reported as
// counters: prep_s (graph + landmarks, seconds), landmarks_s, and prep_MiB, the rise of the
// process's peak resident memory while they ran (Linux: /proc/self/clear_refs resets the peak).
// median_ms and max_ms are over the single queries timed (the time column is their mean).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>
#include <string>

#include "bench_util.h"
#include "mapnav/scenes/route_scene.h"
#include "mapnav/navigator/route.h"

namespace {

using namespace mapnav;
using bench::resetPeakMemory;
using bench::secondsSince;
using bench::statusKb;

struct Campus {
  RouteScene scene;  // the map and its 32 queries
  std::unique_ptr<RoadGraph> graph;
  double graph_s = 0, landmarks_s = 0, prep_mib = 0;
};

Campus& campus(int intersections) {
  static std::map<int, Campus> campuses;
  auto it = campuses.find(intersections);
  if (it != campuses.end()) return it->second;
  Campus c{makeRouteScene(intersections), nullptr};
  resetPeakMemory();
  const double rss0 = statusKb("VmRSS");
  auto t0 = std::chrono::steady_clock::now();
  c.graph = std::make_unique<RoadGraph>(*c.scene.map);
  c.graph_s = secondsSince(t0);
  t0 = std::chrono::steady_clock::now();
  const auto& [from, to] = c.scene.queries.front();
  benchmark::DoNotOptimize(c.graph->route(from, to));  // the first A* query computes the landmarks
  c.landmarks_s = secondsSince(t0);
  c.prep_mib = (statusKb("VmHWM") - rss0) / 1024;
  return campuses.emplace(intersections, std::move(c)).first->second;
}

void BM_RouteQuery(benchmark::State& state) {
  Campus& c = campus(static_cast<int>(state.range(0)));
  RouteOptions options;
  options.use_astar = state.range(1) != 0;
  std::size_t i = 0;
  double length = 0;
  std::vector<double> ms;  // each query's wall time
  for (auto _ : state) {
    const auto& [from, to] = c.scene.queries[i++ % c.scene.queries.size()];
    const auto t0 = std::chrono::steady_clock::now();
    const RouteResult r = c.graph->route(from, to, options);
    ms.push_back(1e3 * secondsSince(t0));
    length += r.route ? r.route->length_m : 0;
    benchmark::DoNotOptimize(r);
  }
  std::sort(ms.begin(), ms.end());
  state.counters["median_ms"] = ms[ms.size() / 2];
  state.counters["max_ms"] = ms.back();
  state.counters["intersections"] = static_cast<double>(c.scene.map->intersections().size());
  state.counters["route_m"] = length / static_cast<double>(state.iterations());
  state.counters["prep_s"] = c.graph_s + c.landmarks_s;
  state.counters["landmarks_s"] = c.landmarks_s;
  state.counters["prep_MiB"] = c.prep_mib;
  state.SetLabel(options.use_astar ? "A*" : "Dijkstra");
}
// Args: intersections, A* (1) or Dijkstra (0). Each iteration is the next of 32 queries, so the
// time is their mean; with --benchmark_repetitions the median of those means is the figure.
BENCHMARK(BM_RouteQuery)
    ->Args({10000, 1})
    ->Args({100000, 1})
    ->Args({1000000, 1})
    ->Args({10000, 0})
    ->Args({100000, 0})
    ->Unit(benchmark::kMillisecond);

}  // namespace
