#pragma once
// What several benchmarks measure beside time: the process's resident memory (Linux
// /proc/self/status) and wall-clock seconds; and the photo-sized frames and the per-frame pipeline
// loop the vision benchmarks share.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "mapnav/image/image.h"
#include "mapnav/mission/image_region.h"
#include "mapnav/scenes/sidewalk_scene.h"
#include "mapnav/vision/pipelines.h"
#include "mapnav/vision/segmentation_eval.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav::bench {

/// A field of /proc/self/status in kB ("VmRSS", "VmHWM"); 0 where there is none.
inline double statusKb(const std::string& field) {
  std::ifstream status("/proc/self/status");
  std::string key;
  double kb = 0;
  while (status >> key) {
    if (key == field + ":") {
      status >> kb;
      return kb;
    }
    status.ignore(1 << 12, '\n');
  }
  return 0;
}

/// Resets the process's peak resident memory (VmHWM) to its current value (Linux).
inline void resetPeakMemory() { std::ofstream("/proc/self/clear_refs") << "5"; }

inline double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// A photo's size (CamVid's), at which the pipelines' per-frame times are reported.
inline constexpr int kPhotoWidth = 480, kPhotoHeight = 360;

/// The sidewalk scene's frames (maps/ of the source tree) at kPhotoWidth x kPhotoHeight, nearest pixel.
inline const std::vector<Image>& photoSizedFrames() {
  static const std::vector<Image> out = [] {
    const SidewalkScene s = makeSidewalkScene(std::string(MAPNAV_SOURCE_DIR) + "/maps");
    std::vector<Image> f;
    for (const Frame& frame : s.frames) {
      Image small(kPhotoWidth, kPhotoHeight, 3);
      for (int v = 0; v < kPhotoHeight; ++v)
        for (int u = 0; u < kPhotoWidth; ++u) {
          const std::uint8_t* p = frame.rgb.pixel(u * frame.rgb.width / kPhotoWidth, v * frame.rgb.height / kPhotoHeight);
          std::copy(p, p + 3, small.pixel(u, v));
        }
      f.push_back(std::move(small));
    }
    return f;
  }();
  return out;
}

/// A pipeline's detect() per frame as `mapnav bench` times it: photoSizedFrames() in turn, the
/// pipeline's defaults, a bottom trapezoid as the prediction. The built-in pipelines are registered
/// here; another (learned) must be registered first.
inline void runPipelineFrames(benchmark::State& state, const std::string& name) {
  registerBuiltinPipelines();
  auto pipeline = createPipeline(name, "{}");
  const std::unique_ptr<Camera> camera = assumedPhotoCamera(kPhotoWidth, kPhotoHeight);
  const PredictedObject prediction =
      predictionFromImageRegion(bottomTrapezoid(kPhotoWidth, kPhotoHeight), *camera).view;
  std::size_t k = 0;
  for (auto _ : state) {
    const Image& rgb = photoSizedFrames()[k++ % photoSizedFrames().size()];
    const VisionFrame frame{kPhotoWidth, kPhotoHeight, rgb.data.data(), camera.get(), static_cast<double>(k), false};
    benchmark::DoNotOptimize(pipeline->detect(frame, prediction).confidence);
  }
}

}  // namespace mapnav::bench
