// Google Benchmark: the edge tracker (Wallace et al. 1985, 3.1) — its oriented step-edge operator on
// one window at the tracker's default size for 480 x 360 (an edge of the sidewalk scene in view),
// fast against the reference form (every sample rounded by std::lround and bounds-checked; the
// same bits, tests/vision/fast_paths_test.cpp), and the whole pipeline's detect() per frame as
// `mapnav bench` times it (the scene's frames at 480 x 360, a bottom trapezoid as the prediction).
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "../vision/src/edge_tracker_internal.h"
#include "mapnav/mission/image_region.h"
#include "mapnav/scenes/sidewalk_scene.h"
#include "mapnav/vision/pipelines.h"
#include "mapnav/vision/segmentation_eval.h"
#include "mapnav/vision_iface/pipeline.h"

namespace {

constexpr int kWidth = 480, kHeight = 360;

// The scene's frames at 480 x 360 (nearest pixel).
const std::vector<mapnav::Image>& frames() {
  static const std::vector<mapnav::Image> out = [] {
    const mapnav::SidewalkScene s = mapnav::makeSidewalkScene(std::string(MAPNAV_SOURCE_DIR) + "/maps");
    std::vector<mapnav::Image> f;
    for (const mapnav::Frame& frame : s.frames) {
      mapnav::Image small(kWidth, kHeight, 3);
      for (int v = 0; v < kHeight; ++v)
        for (int u = 0; u < kWidth; ++u) {
          const std::uint8_t* p = frame.rgb.pixel(u * frame.rgb.width / kWidth, v * frame.rgb.height / kHeight);
          std::copy(p, p + 3, small.pixel(u, v));
        }
      f.push_back(std::move(small));
    }
    return f;
  }();
  return out;
}

void runOperator(benchmark::State& state, bool reference) {
  const mapnav::Image& rgb = frames().front();
  const mapnav::GreyImage grey = mapnav::toGrey(rgb.data.data(), kWidth, kHeight, mapnav::GreyBand::NormalizedGreen);
  const mapnav::OrientedEdgeParams p = mapnav::paramsFor(mapnav::EdgeTrackerOptions{}, kWidth, kHeight);
  const mapnav::Vec2 centre(0.3 * kWidth, 0.75 * kHeight), direction(0.34, -0.94);
  for (auto _ : state) {
    const mapnav::EdgeMatch m = reference ? mapnav::orientedEdgeReference(grey, centre, direction, p)
                                          : mapnav::orientedEdge(grey, centre, direction, p);
    benchmark::DoNotOptimize(m.contrast);
  }
}

void BM_OrientedEdge(benchmark::State& state) { runOperator(state, false); }
void BM_OrientedEdgeReference(benchmark::State& state) { runOperator(state, true); }

void BM_EdgeTrackerFrame(benchmark::State& state) {
  mapnav::registerBuiltinPipelines();
  auto pipeline = mapnav::createPipeline("edge-tracker", "{}");
  const std::unique_ptr<mapnav::Camera> camera = mapnav::assumedPhotoCamera(kWidth, kHeight);
  const mapnav::PredictedObject prediction =
      mapnav::predictionFromImageRegion(mapnav::bottomTrapezoid(kWidth, kHeight), *camera).view;
  std::size_t k = 0;
  for (auto _ : state) {
    const mapnav::Image& rgb = frames()[k++ % frames().size()];
    const mapnav::VisionFrame frame{kWidth, kHeight, rgb.data.data(), camera.get(), static_cast<double>(k), false};
    benchmark::DoNotOptimize(pipeline->detect(frame, prediction).confidence);
  }
}

}  // namespace

BENCHMARK(BM_OrientedEdge)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_OrientedEdgeReference)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EdgeTrackerFrame)->Unit(benchmark::kMillisecond);
