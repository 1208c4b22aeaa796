// Google Benchmark programs for the geometry module's hot paths.
#include <cmath>
#include <random>
#include <vector>

#include <benchmark/benchmark.h>

#include "mapnav/geometry/polygon.h"
#include "mapnav/geometry/polyline2.h"

namespace {

using mapnav::Vec2;

// A random walk with unit steps in uniformly random directions (self-crossing a lot).
std::vector<Vec2> randomWalk(std::size_t vertices, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> angle(-mapnav::kPi, mapnav::kPi);
  std::vector<Vec2> walk{Vec2::Zero()};
  while (walk.size() < vertices) walk.push_back(walk.back() + mapnav::unitVector(angle(rng)));
  return walk;
}

// A road-like curve: unit steps whose heading drifts slowly.
std::vector<Vec2> smoothCurve(std::size_t vertices, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> turn(0.0, 0.05);
  std::vector<Vec2> curve{Vec2::Zero()};
  double heading = 0;
  while (curve.size() < vertices) {
    heading += turn(rng);
    curve.push_back(curve.back() + mapnav::unitVector(heading));
  }
  return curve;
}

void BM_Polyline2Project(benchmark::State& state) {
  const mapnav::Polyline2 line(smoothCurve(static_cast<std::size_t>(state.range(0)), 1));
  const mapnav::Box2 box = line.bounds();
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> x(box.min().x() - 5, box.max().x() + 5);
  std::uniform_real_distribution<double> y(box.min().y() - 5, box.max().y() + 5);
  std::vector<Vec2> queries(1024);
  for (Vec2& q : queries) q = Vec2(x(rng), y(rng));
  std::size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(line.project(queries[k++ & 1023]));
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Polyline2Project)->Arg(1000);

void BM_SelfIntersectionsRandomWalk(benchmark::State& state) {
  const std::vector<Vec2> walk = randomWalk(static_cast<std::size_t>(state.range(0)), 3);
  std::size_t hits = 0;
  for (auto _ : state) {
    const auto result = mapnav::selfIntersections(walk, false);
    hits = result.size();
    benchmark::DoNotOptimize(result.data());
  }
  state.counters["hits"] = static_cast<double>(hits);
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_SelfIntersectionsRandomWalk)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond);

// A long road that barely crosses itself: the common case for map validation.
void BM_SelfIntersectionsSmoothCurve(benchmark::State& state) {
  const std::vector<Vec2> curve = smoothCurve(static_cast<std::size_t>(state.range(0)), 4);
  for (auto _ : state) benchmark::DoNotOptimize(mapnav::selfIntersections(curve, false));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_SelfIntersectionsSmoothCurve)->Arg(100000)->Unit(benchmark::kMillisecond);

}  // namespace
