// Google Benchmark: the park-mode road finder (Jochem & Baluja 1993, §6 runtime) per colour frame,
// single-threaded, at several sizes: the fast path (colour lookup table, block Hough), the per-pixel
// reference path, and a plain memcpy of the same frame for scale. The scene (camera, frames, training)
// is the one `mapnav bench` uses: apps/src/park_scene.h.
#include <benchmark/benchmark.h>

#include <cstring>
#include <map>
#include <vector>

#include "mapnav/map/map_io.h"
#include "park_scene.h"  // the scene `mapnav bench` times too (apps/src)

namespace {

const mapnav::Map& parkMap() {
  static const mapnav::Map map = mapnav::loadMap(std::string(MAPNAV_SOURCE_DIR) + "/maps/park_path.json");
  return map;
}

struct Setup {
  mapnav::cli::ParkScene scene;  // a few consecutive frames along R1
  mapnav::ClusterPerceptron finder;
};

// The shared park scene at size × size, trained on the first frame from the predicted road outline;
// built once per size.
const Setup& setup(int size) {
  static std::map<int, Setup> cache;
  auto it = cache.find(size);
  if (it != cache.end()) return it->second;
  mapnav::cli::ParkScene scene = mapnav::cli::makeParkScene(parkMap(), size);
  mapnav::ClusterPerceptron finder = mapnav::cli::trainParkFinder(scene, mapnav::cli::parkFinderOptions(size)).finder;
  Setup s{std::move(scene), std::move(finder)};
  return cache.emplace(size, std::move(s)).first->second;
}

void counters(benchmark::State& state, int size) {
  const double n = static_cast<double>(state.iterations());
  state.counters["fps"] = benchmark::Counter(n, benchmark::Counter::kIsRate);
  state.counters["px/s"] = benchmark::Counter(n * size * size, benchmark::Counter::kIsRate);
}

void runFinder(benchmark::State& state, bool fast) {
  const int size = static_cast<int>(state.range(0));
  const Setup& s = setup(size);
  mapnav::ClusterPerceptron finder = s.finder;
  finder.setFast(fast);
  std::size_t k = 0;
  for (auto _ : state) {
    const mapnav::Image& f = s.scene.frames[k++ % s.scene.frames.size()].rgb;
    mapnav::RoadFinding r = finder.find(f.data.data(), size, size, false);
    benchmark::DoNotOptimize(r.centerline_image);
  }
  counters(state, size);
}

// The runtime (§6): lookup-table classification, block certainty, Hough and refinement; no mask.
void BM_ParkRoadFinderFast(benchmark::State& state) { runFinder(state, true); }
// The same with the per-pixel reference classification (float distance to every cluster, std::tanh).
void BM_ParkRoadFinderReference(benchmark::State& state) { runFinder(state, false); }

// A plain copy of the same frame, for scale.
void BM_ParkFrameMemcpy(benchmark::State& state) {
  const int size = static_cast<int>(state.range(0));
  const Setup& s = setup(size);
  std::vector<std::uint8_t> dst(s.scene.frames.front().rgb.data.size());
  std::size_t k = 0;
  for (auto _ : state) {
    const mapnav::Image& f = s.scene.frames[k++ % s.scene.frames.size()].rgb;
    std::memcpy(dst.data(), f.data.data(), f.data.size());
    benchmark::DoNotOptimize(dst.data());
    benchmark::ClobberMemory();
  }
  counters(state, size);
}

BENCHMARK(BM_ParkRoadFinderFast)->Arg(64)->Arg(128)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ParkRoadFinderReference)->Arg(64)->Arg(128)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ParkFrameMemcpy)->Arg(64)->Arg(128)->Arg(256)->Arg(512)->Arg(1024)->Unit(benchmark::kMicrosecond);

}  // namespace
