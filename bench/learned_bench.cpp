// Google Benchmark: the learned road segmentation (docs/learned.md) — the network's road probability
// for one 480 x 360 photo-sized frame with the committed camvid model (input 240 x 180) on one
// Torch thread, as the learned pipeline computes it for every frame at its defaults; and the whole
// pipeline's detect() per frame (the probability, its region, polygon and centre line).
#include <benchmark/benchmark.h>

#include <string>
#include <vector>

#include "bench_util.h"
#include "mapnav/image/image.h"
#include "mapnav/learned/learned_pipeline.h"
#include "mapnav/learned/segmentation_model.h"

namespace {

const mapnav::SegmentationModel& model() {
  static const mapnav::SegmentationModel m = mapnav::SegmentationModel::load(mapnav::resolveSegmentationModel("camvid"));
  return m;
}

void BM_LearnedRoadProbability(benchmark::State& state) {
  using mapnav::bench::kPhotoHeight, mapnav::bench::kPhotoWidth;
  const mapnav::Image& rgb = mapnav::bench::photoSizedFrames().front();
  const std::vector<std::uint8_t> ground(static_cast<std::size_t>(kPhotoWidth) * kPhotoHeight, 1);
  mapnav::SegmentationModel::setThreads(1);  // the learned pipeline's default
  for (auto _ : state) {
    const std::vector<float> p = model().roadProbability(rgb.data.data(), kPhotoWidth, kPhotoHeight, ground.data());
    benchmark::DoNotOptimize(p.data());
  }
}

void BM_LearnedFrame(benchmark::State& state) {
  mapnav::registerLearnedPipeline();
  mapnav::bench::runPipelineFrames(state, "learned");
}

}  // namespace

BENCHMARK(BM_LearnedRoadProbability)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LearnedFrame)->Unit(benchmark::kMillisecond);
