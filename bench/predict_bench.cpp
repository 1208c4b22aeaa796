// Predicted views per second on generated grid campuses of about 1k, 10k and 100k roads. The
// prediction queries the map's R-tree, so its cost should grow with what is in view, not with the
// map: the ratio printed at the end, time(100k) / time(1k), should stay small (target ≤ 3).
// BM_PredictView is one frame of a fresh ViewPredictor (what predictView does); BM_ViewPredictor
// keeps one across the frames, as the Map module does, so each road's segments are worked out once;
// BM_ViewPredictorCampus is the Map module's case: the campus with the mission camera.
#include <benchmark/benchmark.h>

#include <map>
#include <memory>
#include <random>

#include "mapnav/geometry/camera_io.h"
#include "mapnav/map/generate.h"
#include "mapnav/map/map_io.h"
#include "mapnav/map/predict.h"

namespace {

using namespace mapnav;

struct Scene {
  std::unique_ptr<Map> map;
  std::vector<Pose2> poses;
};

// The grid with about `roads` roads, and 64 poses on its roads looking along them (seeded).
const Scene& scene(int roads) {
  static std::map<int, Scene> scenes;
  auto it = scenes.find(roads);
  if (it != scenes.end()) return it->second;
  GridMapOptions options;
  // columns = rows = n gives 2 n (n - 1) roads.
  int n = 2;
  while (2 * n * (n - 1) < roads) ++n;
  options.columns = options.rows = n;
  Scene s;
  s.map = std::make_unique<Map>(makeGridMap(options));
  std::mt19937 rng(7);
  std::uniform_int_distribution<std::size_t> pick(0, s.map->roads().size() - 1);
  std::uniform_real_distribution<double> along(2.0, 38.0);
  for (int i = 0; i < 64; ++i) {
    const Road& road = s.map->roads()[pick(rng)];
    const double d = along(rng);
    s.poses.emplace_back(road.centerline.pointAt(d), road.centerline.headingAt(d));
  }
  return scenes.emplace(roads, std::move(s)).first->second;
}

std::unique_ptr<Camera> terregatorLikePinhole() {
  CameraIntrinsics in;
  in.width = 512;
  in.height = 480;
  in.fx = in.fy = 560;
  in.cx = 255.5;
  in.cy = 239.5;
  CameraMount mount;
  mount.height_m = 1.5;
  mount.tilt_rad = 0.38;
  return createCamera(LensModel::Pinhole, in, mount);
}

void BM_PredictView(benchmark::State& state) {
  const Scene& s = scene(static_cast<int>(state.range(0)));
  const auto camera = terregatorLikePinhole();
  std::size_t i = 0, segments = 0;
  for (auto _ : state) {
    const Prediction p = predictView(*s.map, s.poses[i++ % s.poses.size()], *camera);
    segments += p.view.segments.size();
    benchmark::DoNotOptimize(p);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
  state.counters["roads"] = static_cast<double>(s.map->roads().size());
  state.counters["segments_per_view"] = static_cast<double>(segments) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_PredictView)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);

void BM_ViewPredictor(benchmark::State& state) {
  const Scene& s = scene(static_cast<int>(state.range(0)));
  const auto camera = terregatorLikePinhole();
  ViewPredictor predictor(*s.map);
  std::size_t i = 0;
  for (auto _ : state) {
    const Prediction p = predictor.predict(s.poses[i++ % s.poses.size()], *camera);
    benchmark::DoNotOptimize(p);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
}
BENCHMARK(BM_ViewPredictor)->Arg(1000)->Arg(10000)->Arg(100000)->Unit(benchmark::kMicrosecond);

// The campus with the missions' pin-hole camera, from every 2 m of every road, both ways.
void BM_ViewPredictorCampus(benchmark::State& state) {
  static const Map map = loadMap(std::string(MAPNAV_SOURCE_DIR) + "/maps/cmu_campus.json");
  static const auto camera = loadCamera(std::string(MAPNAV_SOURCE_DIR) + "/maps/cameras/terregator_pinhole.json");
  static const std::vector<Pose2> poses = [] {
    std::vector<Pose2> out;
    for (const Road& road : map.roads()) {
      for (double d = 1.0; d < road.centerline.length(); d += 2.0) {
        out.emplace_back(road.centerline.pointAt(d), road.centerline.headingAt(d));
        out.emplace_back(road.centerline.pointAt(d), road.centerline.headingAt(d) + kPi);
      }
    }
    return out;
  }();
  ViewPredictor predictor(map);
  std::size_t i = 0, segments = 0;
  for (auto _ : state) {
    const Prediction p = predictor.predict(poses[i++ % poses.size()], *camera);
    segments += p.view.segments.size();
    benchmark::DoNotOptimize(p);
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()));
  state.counters["segments_per_view"] = static_cast<double>(segments) / static_cast<double>(state.iterations());
}
BENCHMARK(BM_ViewPredictorCampus)->Unit(benchmark::kMicrosecond);

}  // namespace
