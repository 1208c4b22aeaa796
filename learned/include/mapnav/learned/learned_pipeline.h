#pragma once
// The "learned" vision pipeline (docs/learned.md): a SegmentationModel's road probability per
// pixel, then the region, polygon, lines and their labels of every region pipeline (ScorePipeline).
// It trains nothing on the prediction: the prediction only says which region is the road and which
// lines are which.
#include <filesystem>
#include <string>

#include "mapnav/core/option_table.h"
#include "mapnav/vision/pipelines.h"

namespace mapnav {

struct LearnedPipelineOptions : ScorePipelineOptions {
  /// A model file, or the name of a committed model: "camvid" (road and pavement, trained on
  /// ../shared/data/real/camvid_train) or "sim" (the simulator's paths, trained on its logs).
  std::string model = "camvid";
  int threads = 1;  ///< Torch's CPU threads for this process; 0 = Torch's default (every core)

  /// Throws InvalidInput "LearnedPipelineOptions::FIELD = VALUE: must be ..." for a field out of range.
  void validate() const;
};

const OptionTable<LearnedPipelineOptions>& learnedPipelineOptionTable();

/// A model name or path to its file: an existing file as it is; a name ("camvid") to NAME.mnseg in
/// the installed models folder (<prefix>/share/mapnav/models, found from the running program) or
/// in the source tree's models/. Throws NotFound listing where it looked.
std::filesystem::path resolveSegmentationModel(const std::string& name_or_path);

/// Registers "learned" (once; thread-safe).
void registerLearnedPipeline();

}  // namespace mapnav
