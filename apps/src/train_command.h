#pragma once
// `mapnav train segmentation` (docs/learned.md): trains the learned pipeline's network on labelled
// photos. Built only with the learned segmentation (MAPNAV_LEARNED).
#include <iosfwd>
#include <string>

#include "mapnav/eval/training_set.h"
#include "mapnav/learned/train_segmentation.h"

namespace mapnav::cli {

struct TrainSegmentationConfig {
  TrainingSet set;             ///< photos and logs to train on
  SegmentationTrainOptions options;
  std::string output;          ///< the model file, written atomically
  std::string command;         ///< the command line, recorded in the model
  bool json = false;
};

int runTrainSegmentation(const TrainSegmentationConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
