#pragma once
// What a program reaches of learned/ without linking it: Torch's libraries take about half a second
// to load and initialise, which every `mapnav` command would pay. The CLI opens
// libmapnav_learned.so only when a command needs it (the "learned" pipeline, `mapnav train`) and
// finds this table by name (kLearnedApiSymbol). No Torch here: the types are the torch-free ones of
// train_segmentation.h.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "mapnav/learned/train_segmentation.h"

namespace mapnav {

/// What a training made and wrote.
struct TrainedModelSummary {
  std::size_t parameters = 0;
  int width = 0, height = 0;
  SegmentationTraining training;
};

struct LearnedApi {
  /// trainSegmentation() with `command` recorded, then the model written atomically to `output`.
  /// Throws as trainSegmentation (options validated first) and SegmentationModel::save.
  TrainedModelSummary (*train)(const std::vector<TrainingPhoto>& photos, const SegmentationTrainOptions& options,
                               const std::function<void(const EpochReport&)>& progress, const std::string& command,
                               const std::string& output);
};

/// The extern "C" function of libmapnav_learned.so that returns its LearnedApi (`const LearnedApi*
/// mapnav_learned_api()`); the library's `mapnav_register_pipelines` registers "learned".
inline constexpr const char* kLearnedApiSymbol = "mapnav_learned_api";

}  // namespace mapnav
