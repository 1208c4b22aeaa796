// Google Benchmark: the park-mode road finder (Jochem & Baluja 1993, §6 runtime) per colour frame,
// single-threaded, at several sizes: the fast path (colour lookup table, block Hough), the per-pixel
// reference path, and a plain memcpy of the same frame for scale.
#include <benchmark/benchmark.h>

#include <cstring>
#include <map>
#include <memory>
#include <vector>

#include "mapnav/map/map_io.h"
#include "mapnav/map/predict.h"
#include "mapnav/sim/world.h"
#include "mapnav/vision/cluster_perceptron.h"

namespace {

const mapnav::Map& parkMap() {
  static const mapnav::Map map = mapnav::loadMap(std::string(MAPNAV_SOURCE_DIR) + "/maps/park_path.json");
  return map;
}

struct Setup {
  std::unique_ptr<mapnav::Camera> camera;
  std::vector<mapnav::Frame> frames;  // a few consecutive frames along R1
  std::unique_ptr<mapnav::ClusterPerceptron> finder;
};

// A size × size Terregator-like pin-hole (f scaled with the size) on the park path, trained on the
// first frame from the predicted road outline; built once per size.
const Setup& setup(int size) {
  static std::map<int, Setup> cache;
  auto it = cache.find(size);
  if (it != cache.end()) return it->second;
  Setup s;
  mapnav::CameraIntrinsics in;
  in.width = in.height = size;
  in.fx = in.fy = 904.0 * size / 512.0;
  in.cx = in.cy = (size - 1) / 2.0;
  mapnav::CameraMount mount;
  mount.tilt_rad = mapnav::degToRad(22.0);
  s.camera = mapnav::createCamera(mapnav::LensModel::Pinhole, in, mount);
  mapnav::WorldOptions options;
  options.shadow_density = 0.4;
  const mapnav::World world(parkMap(), options);
  const mapnav::RayTable rays(*s.camera);
  const double heading = std::atan2(6.946, 39.392);
  for (int k = 0; k < 4; ++k) {
    const double d = 5.0 + 2.0 * k;
    s.frames.push_back(
        world.render(rays, mapnav::Pose2(mapnav::Vec2(d * std::cos(heading), d * std::sin(heading)), heading), k));
  }
  const mapnav::Prediction pred = mapnav::predictView(parkMap(), mapnav::Pose2(mapnav::Vec2(5.0 * std::cos(heading),
                                                                                            5.0 * std::sin(heading)),
                                                                               heading),
                                                      *s.camera);
  const mapnav::Image outline = mapnav::predictedRoadMask(pred.view, *s.camera);
  mapnav::ClusterPerceptronOptions o;
  o.block_size = std::max(2, 8 * size / 512);
  s.finder = std::make_unique<mapnav::ClusterPerceptron>(o);
  const mapnav::Image& f0 = s.frames.front().rgb;
  s.finder->trainClusters(f0.data.data(), size, size);
  s.finder->setRowWidths(mapnav::trapezoidRowWidths(outline));
  s.finder->trainPerceptron(f0.data.data(), size, size, outline.data.data());
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
  mapnav::ClusterPerceptron finder = *s.finder;
  finder.setFast(fast);
  std::size_t k = 0;
  for (auto _ : state) {
    const mapnav::Image& f = s.frames[k++ % s.frames.size()].rgb;
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
  std::vector<std::uint8_t> dst(s.frames.front().rgb.data.size());
  std::size_t k = 0;
  for (auto _ : state) {
    const mapnav::Image& f = s.frames[k++ % s.frames.size()].rgb;
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
