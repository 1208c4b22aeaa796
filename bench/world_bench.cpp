// Google Benchmark: synthetic camera frames per second (sim/world.h) on the campus map, beside a
// plain copy of a frame of the same size (the ratio render / memcpy says how far from memory speed),
// and with ten map landmarks in view against none.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "mapnav/map/map_io.h"
#include "mapnav/sim/world.h"

namespace {

const mapnav::Map& campusMap() {
  static const mapnav::Map map = mapnav::loadMap(std::string(MAPNAV_SOURCE_DIR) + "/maps/cmu_campus.json");
  return map;
}

// A width × height frame from the Terregator pin-hole (f scaled with the width; 512 × 480 is the
// camera of maps/cameras/), moving along R1 0.1 m a frame; the third argument is
// WorldOptions::paved_edge_samples (1: point sampling; 4: the pixels the paved area's edge crosses
// area-sampled 4 × 4), the fourth 1 for the texel cache (texel_cache_mib 64) and 0 for the
// per-pixel renderer (the default), so that their costs are ratios in the same run.
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
  if (state.range(3) == 1) options.texel_cache_mib = 64;
  const mapnav::World world(campusMap(), options);
  const mapnav::RayTable rays(*camera);
  double t = 0;
  (void)world.render(rays, mapnav::Pose2(53 - 0.1, 40, 0), 0);  // the drive's frame before: as mapnav bench's
  for (auto _ : state) {
    const mapnav::Frame frame = world.render(rays, mapnav::Pose2(53 + t, 40, 0), t);
    benchmark::DoNotOptimize(frame.rgb.data.data());
    t += 0.1;
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_RenderFrame)
    ->Args({512, 480, 1, 1})
    ->Args({512, 480, 1, 0})
    ->Args({512, 480, 4, 1})
    ->Args({512, 512, 1, 1})
    ->Unit(benchmark::kMillisecond);

// The campus with n landmarks 2.5 … 11 m ahead of the camera of BM_LandmarksInView beside R1 (and a
// manhole cover in it): poles, trees, bollards, benches and covers in turn, the kinds' own sizes.
const mapnav::Map& campusWithLandmarks(int n) {
  static std::map<int, mapnav::Map> maps;
  if (const auto it = maps.find(n); it != maps.end()) return it->second;
  mapnav::MapData data = campusMap().data();
  using K = mapnav::LandmarkKind;
  const K kinds[] = {K::Pole, K::Tree, K::Bollard, K::Bench, K::Manhole};
  for (int i = 0; i < n; ++i) {
    mapnav::Landmark l;
    l.id = "L" + std::to_string(i);
    l.kind = kinds[i % 5];
    l.radius = mapnav::defaultLandmarkSize(l.kind).radius_m;
    l.height = mapnav::defaultLandmarkSize(l.kind).height_m;
    const double side = i % 2 == 0 ? 1.0 : -1.0, off = l.kind == K::Manhole ? 0.4 : l.kind == K::Bench ? 2.4 : 2.0;
    l.position = mapnav::Vec2(57.5 + 0.75 * i, 40 + side * off);
    data.landmarks.push_back(l);
  }
  return maps.emplace(n, mapnav::Map(std::move(data), "campus with landmarks")).first->second;
}

// A 512 × 480 frame of the Terregator pin-hole on R1 with n = the argument landmarks in view (all of
// them, from every pose of the run: the camera moves 0 … 2 m and back), so that their cost is the
// ratio of the rows in the same run.
void BM_LandmarksInView(benchmark::State& state) {
  mapnav::CameraIntrinsics in;
  in.width = 512;
  in.height = 480;
  in.fx = in.fy = 904.0;
  in.cx = 255.5;
  in.cy = 239.5;
  mapnav::CameraMount mount;
  mount.tilt_rad = mapnav::degToRad(22.0);
  const auto camera = mapnav::createCamera(mapnav::LensModel::Pinhole, in, mount);
  mapnav::WorldOptions options;
  options.shadow_density = 0.3;
  const mapnav::World world(campusWithLandmarks(static_cast<int>(state.range(0))), options);
  const mapnav::RayTable rays(*camera);
  std::size_t shown = 0;
  int k = 0;
  for (auto _ : state) {
    const double t = 0.1 * (k++ % 20);
    const mapnav::Frame frame = world.render(rays, mapnav::Pose2(53 + t, 40, 0), t);
    shown += frame.landmarks.size();
    benchmark::DoNotOptimize(frame.rgb.data.data());
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["listed"] = static_cast<double>(shown) / static_cast<double>(std::max<std::int64_t>(1, state.iterations()));
}
BENCHMARK(BM_LandmarksInView)->Arg(0)->Arg(10)->Unit(benchmark::kMillisecond);

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
