// Google Benchmark: the park-mode road finder (Jochem & Baluja 1993, §6 runtime) per colour frame,
// single-threaded, at several sizes: the fast path (colour lookup table, block Hough), the per-pixel
// reference path, and a plain memcpy of the same frame for scale. The scene (camera, frames, training)
// is the one `mapnav bench` uses: mapnav/scenes/park_scene.h.
#include <benchmark/benchmark.h>

#include <cstring>
#include <map>
#include <vector>

#include "mapnav/map/map_io.h"
#include "mapnav/scenes/park_scene.h"  // the scene `mapnav bench` times too

namespace {

const mapnav::Map& parkMap() {
  static const mapnav::Map map = mapnav::loadMap(std::string(MAPNAV_SOURCE_DIR) + "/maps/park_path.json");
  return map;
}

struct Setup {
  mapnav::ParkScene scene;  // a few consecutive frames along R1
  mapnav::ClusterPerceptron finder;
};

/// `mapnav bench`'s finder options at size × size; `normalised`: in normalised colour with 8 clusters
/// (ClusterPerceptronOptions::normalized_color, as its tests use it).
mapnav::ClusterPerceptronOptions finderOptions(int size, bool normalised) {
  mapnav::ClusterPerceptronOptions o = mapnav::parkFinderOptions(size);
  if (normalised) {
    o.normalized_color = true;
    o.clusters = 8;
  }
  return o;
}

// The shared park scene at size × size, trained on the first frame from the predicted road outline;
// built once per size and colour space.
const Setup& setup(int size, bool normalised = false) {
  static std::map<std::pair<int, bool>, Setup> cache;
  auto it = cache.find({size, normalised});
  if (it != cache.end()) return it->second;
  mapnav::ParkScene scene = mapnav::makeParkScene(parkMap(), size);
  mapnav::ClusterPerceptron finder = mapnav::trainParkFinder(scene, finderOptions(size, normalised)).finder;
  Setup s{std::move(scene), std::move(finder)};
  return cache.emplace(std::make_pair(size, normalised), std::move(s)).first->second;
}

void counters(benchmark::State& state, int size) {
  const double n = static_cast<double>(state.iterations());
  state.counters["fps"] = benchmark::Counter(n, benchmark::Counter::kIsRate);
  state.counters["px/s"] = benchmark::Counter(n * size * size, benchmark::Counter::kIsRate);
}

void runFinder(benchmark::State& state, bool fast, bool normalised = false) {
  const int size = static_cast<int>(state.range(0));
  const Setup& s = setup(size, normalised);
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
// The runtime in normalised colour (8 clusters): the lookup table absorbs the normalisation.
void BM_ParkRoadFinderFastNormalised(benchmark::State& state) { runFinder(state, true, true); }

// Training on the first frame (clustering, perceptron; the lookup table's cells are computed by the
// first two find() calls after it, the first frame's cells and then the rest); range(1) = normalised
// colour with 8 clusters.
void BM_ParkTraining(benchmark::State& state) {
  const int size = static_cast<int>(state.range(0));
  const bool normalised = state.range(1) != 0;
  const Setup& s = setup(size);
  for (auto _ : state) {
    mapnav::TrainedParkFinder t = mapnav::trainParkFinder(s.scene, finderOptions(size, normalised));
    benchmark::DoNotOptimize(t.finder.weights().data());
  }
}

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
BENCHMARK(BM_ParkRoadFinderFastNormalised)->Arg(512)->Arg(1024)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ParkTraining)->Args({512, 0})->Args({512, 1})->Unit(benchmark::kMillisecond);

}  // namespace
