#pragma once
// `mapnav bench`'s vision pipelines row by row (internal to apps/): every registered region and park
// pipeline, the learned one where it is built, timed on the same frames at two frame sizes, on one
// thread and (where the pipeline has a `threads` option) on more.
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/core/json.h"
#include "mapnav/scenes/sidewalk_scene.h"

namespace mapnav::cli {

struct PipelineTime {
  std::string pipeline;
  int width = 0, height = 0, threads = 1;
  double ms = 0;  ///< median detect() time per frame
};

/// detect() with a bottom trapezoid as the prediction on `scene`'s frames resized to 480x360 and at
/// their own 512x480, each pipeline on 1 thread and on `threads` where it has a `threads` option:
/// the pipelines `names` (every registered one without them). Throws NotFound for an unknown name.
std::vector<PipelineTime> timePipelines(const SidewalkScene& scene, int threads, double min_time_s,
                                        const std::optional<std::vector<std::string>>& names = std::nullopt);

/// The table, each time beside sidewalk's at the same size on one thread (a ratio of one run).
void printPipelineTimes(const std::vector<PipelineTime>& times, std::ostream& out);
Json pipelineTimesJson(const std::vector<PipelineTime>& times);

}  // namespace mapnav::cli
