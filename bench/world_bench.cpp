// Google Benchmark: synthetic camera frames per second (sim/world.h) on the campus map.
#include <benchmark/benchmark.h>

#include "mapnav/map/map_io.h"
#include "mapnav/sim/world.h"

namespace {

const mapnav::Map& campusMap() {
  static const mapnav::Map map = mapnav::loadMap(std::string(MAPNAV_SOURCE_DIR) + "/maps/cmu_campus.json");
  return map;
}

// A size × size frame from the Terregator pin-hole (f scaled with the size), moving along R1; the
// second argument is WorldOptions::paved_edge_samples (1: point sampling; 4: the pixels the paved
// area's edge crosses area-sampled 4 × 4), so that its cost is a ratio in the same run.
void BM_RenderFrame(benchmark::State& state) {
  const int size = static_cast<int>(state.range(0));
  mapnav::CameraIntrinsics in;
  in.width = in.height = size;
  in.fx = in.fy = 904.0 * size / 512.0;
  in.cx = in.cy = (size - 1) / 2.0;
  mapnav::CameraMount mount;
  mount.tilt_rad = mapnav::degToRad(22.0);
  const auto camera = mapnav::createCamera(mapnav::LensModel::Pinhole, in, mount);
  mapnav::WorldOptions options;
  options.shadow_density = 0.3;
  options.paved_edge_samples = static_cast<int>(state.range(1));
  const mapnav::World world(campusMap(), options);
  const mapnav::RayTable rays(*camera);
  double t = 0;
  for (auto _ : state) {
    const mapnav::Frame frame = world.render(rays, mapnav::Pose2(53 + t, 40, 0), t);
    benchmark::DoNotOptimize(frame.rgb.data.data());
    t += 0.1;
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderFrame)->Args({512, 1})->Args({512, 4})->Unit(benchmark::kMillisecond);

}  // namespace
