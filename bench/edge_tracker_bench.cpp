// Google Benchmark: the edge tracker (Wallace et al. 1985, 3.1) — its oriented step-edge operator on
// one window at the tracker's default size for 480 x 360 (an edge of the sidewalk scene in view),
// fast against the reference form (every sample rounded by std::lround and bounds-checked; the
// same bits, tests/vision/fast_paths_test.cpp), and the whole pipeline's detect() per frame as
// `mapnav bench` times it (the scene's frames at 480 x 360, a bottom trapezoid as the prediction).
#include <benchmark/benchmark.h>

#include "../vision/src/edge_tracker_internal.h"
#include "bench_util.h"

namespace {

using mapnav::bench::kPhotoHeight, mapnav::bench::kPhotoWidth;
constexpr int kWidth = kPhotoWidth, kHeight = kPhotoHeight;
using mapnav::bench::photoSizedFrames, mapnav::bench::runPipelineFrames;

void runOperator(benchmark::State& state, bool reference) {
  const mapnav::Image& rgb = photoSizedFrames().front();
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

void BM_EdgeTrackerFrame(benchmark::State& state) { runPipelineFrames(state, "edge-tracker"); }
// The cluster-perceptron road finder the same way: each detect() trains on its frame (clustering,
// perceptron, the lookup table's cells of its colours) and classifies it.
void BM_ClusterPerceptronFrame(benchmark::State& state) { runPipelineFrames(state, "cluster-perceptron"); }

}  // namespace

BENCHMARK(BM_OrientedEdge)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_OrientedEdgeReference)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EdgeTrackerFrame)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ClusterPerceptronFrame)->Unit(benchmark::kMillisecond);
