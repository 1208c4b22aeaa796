// Google Benchmark: the default Vision pipeline ("sidewalk": colour classification, region
// reproduction, polygon fitting, line labelling) per frame at 512 x 480 on the campus scene of
// mapnav/scenes/sidewalk_scene.h — the default (grid_px 2: 2 x 2-pixel cells, fast paths), every pixel (grid_px 1, fast
// paths), the reference (option "reference": every pixel, reference implementations), a plain memcpy of the frame for scale, and the Map's prediction plus Vision, the two
// costly steps of the mission loop.
#include <benchmark/benchmark.h>

#include <cstring>
#include <string>
#include <vector>

#include "mapnav/map/predict.h"
#include "mapnav/vision/ground_step.h"
#include "mapnav/vision/pipelines.h"
#include "mapnav/vision_iface/pipeline.h"
#include "mapnav/scenes/sidewalk_scene.h"  // the scene `mapnav bench` times too

namespace {

const mapnav::SidewalkScene& scene() {
  static const mapnav::SidewalkScene s = mapnav::makeSidewalkScene(std::string(MAPNAV_SOURCE_DIR) + "/maps");
  return s;
}

void runSidewalk(benchmark::State& state, const char* options, bool predict) {
  const auto& s = scene();
  mapnav::registerBuiltinPipelines();
  auto pipeline = mapnav::createPipeline("sidewalk", options);
  mapnav::ViewPredictor predictor(s.map);  // kept across frames, as the Map module keeps one
  std::size_t k = 0;
  for (auto _ : state) {
    const std::size_t i = k++ % s.frames.size();
    const mapnav::Image& rgb = s.frames[i].rgb;
    const mapnav::VisionFrame frame{rgb.width, rgb.height, rgb.data.data(), s.camera.get(), static_cast<double>(k)};
    if (predict) {
      const mapnav::Prediction p = predictor.predict(s.poses[i], *s.camera);
      benchmark::DoNotOptimize(pipeline->detect(frame, p.view).lines.data());
    } else {
      benchmark::DoNotOptimize(pipeline->detect(frame, s.predictions[i]).lines.data());
    }
  }
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_SidewalkFrame(benchmark::State& state) { runSidewalk(state, "{}", false); }
void BM_SidewalkFrameEveryPixel(benchmark::State& state) { runSidewalk(state, R"({"grid_px": 1})", false); }
void BM_SidewalkFrameReference(benchmark::State& state) { runSidewalk(state, R"({"reference": true})", false); }
void BM_SidewalkPredictAndFrame(benchmark::State& state) { runSidewalk(state, "{}", true); }

// The ground's step between consecutive frames, which the Vision module adds to every
// pipeline; "found" is the share of pairs that registered.
void BM_GroundStep(benchmark::State& state) {
  const auto& s = scene();
  std::size_t k = 0, found = 0;
  for (auto _ : state) {
    const std::size_t i = k++ % (s.frames.size() - 1);
    const mapnav::Image &a = s.frames[i].rgb, &b = s.frames[i + 1].rgb;
    const mapnav::Pose2 step = s.poses[i].inverse() * s.poses[i + 1];
    const mapnav::VisionFrame before{a.width, a.height, a.data.data(), s.camera.get(), 0.0};
    const mapnav::VisionFrame after{b.width, b.height, b.data.data(), s.camera.get(), 1.0};
    const mapnav::MeasuredStep m = mapnav::measureGroundStep(before, after, {step.translation().norm(), step.heading()});
    found += m.found ? 1 : 0;
    benchmark::DoNotOptimize(m.distance_m);
  }
  state.counters["found"] = static_cast<double>(found) / static_cast<double>(k);
}

void BM_SidewalkMemcpy(benchmark::State& state) {
  const auto& s = scene();
  std::vector<std::uint8_t> dst(s.frames.front().rgb.data.size());
  std::size_t k = 0;
  for (auto _ : state) {
    const mapnav::Image& f = s.frames[k++ % s.frames.size()].rgb;
    std::memcpy(dst.data(), f.data.data(), f.data.size());
    benchmark::DoNotOptimize(dst.data());
    benchmark::ClobberMemory();
  }
}

}  // namespace

BENCHMARK(BM_SidewalkFrame)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SidewalkFrameEveryPixel)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SidewalkFrameReference)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SidewalkPredictAndFrame)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GroundStep)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SidewalkMemcpy)->Unit(benchmark::kMicrosecond);
