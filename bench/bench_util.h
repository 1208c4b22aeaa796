#pragma once
// What several benchmarks measure beside time: the process's resident memory (Linux
// /proc/self/status) and wall-clock seconds; and the photo-sized frames the vision benchmarks share.
#include <algorithm>
#include <chrono>
#include <fstream>
#include <string>
#include <vector>

#include "mapnav/image/image.h"
#include "mapnav/scenes/sidewalk_scene.h"

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

}  // namespace mapnav::bench

namespace benchmark {
class State;
}  // namespace benchmark

/// A pipeline's detect() per frame at kPhotoWidth x kPhotoHeight, its defaults, a bottom trapezoid as
/// the prediction (edge_tracker_bench.cpp); the pipeline must be registered.
void runPipelineFrames(benchmark::State& state, const std::string& name);
