// Google Benchmark: synthetic camera frames per second (sim/world.h) on the campus map, beside a
// plain copy of a frame of the same size (the ratio render / memcpy says how far from memory speed).
#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstring>
#include <vector>

#include "mapnav/map/map_io.h"
#include "mapnav/sim/world.h"

namespace {

const mapnav::Map& campusMap() {
  static const mapnav::Map map = mapnav::loadMap(std::string(MAPNAV_SOURCE_DIR) + "/maps/cmu_campus.json");
  return map;
}

// A width × height frame from the Terregator pin-hole (f scaled with the width; 512 × 480 is the
// camera of maps/cameras/), moving along R1; the third argument is WorldOptions::paved_edge_samples
// (1: point sampling; 4: the pixels the paved area's edge crosses area-sampled 4 × 4), so that its
// cost is a ratio in the same run.
void BM_RenderFrame(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0)), height = static_cast<int>(state.range(1));
  mapnav::CameraIntrinsics in;
  in.width = width;
  in.height = height;
  in.fx = in.fy = 904.0 * width / 512.0;
  in.cx = (width - 1) / 2.0;
  in.cy = (height - 1) / 2.0;
  mapnav::CameraMount mount;
  mount.tilt_rad = mapnav::degToRad(22.0);
  const auto camera = mapnav::createCamera(mapnav::LensModel::Pinhole, in, mount);
  mapnav::WorldOptions options;
  options.shadow_density = 0.3;
  options.paved_edge_samples = static_cast<int>(state.range(2));
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
BENCHMARK(BM_RenderFrame)->Args({512, 480, 1})->Args({512, 480, 4})->Args({512, 512, 1})->Unit(benchmark::kMillisecond);

// A plain copy of a rendered frame (its colour and mask planes) of the same size, for scale.
void BM_RenderFrameMemcpy(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0)) * static_cast<std::size_t>(state.range(1));
  const std::vector<std::uint8_t> rgb(3 * n, 90), mask(n, 255);
  std::vector<std::uint8_t> rgb_out(3 * n), mask_out(n);
  for (auto _ : state) {
    std::memcpy(rgb_out.data(), rgb.data(), rgb.size());
    std::memcpy(mask_out.data(), mask.data(), mask.size());
    benchmark::DoNotOptimize(rgb_out.data());
    benchmark::DoNotOptimize(mask_out.data());
    benchmark::ClobberMemory();
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderFrameMemcpy)->Args({512, 480})->Args({512, 512})->Unit(benchmark::kMicrosecond);

}  // namespace
