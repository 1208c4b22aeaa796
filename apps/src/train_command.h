#pragma once
// `mapnav train segmentation` (docs/learned.md): trains the learned pipeline's network on labelled
// photos. Built only with the learned segmentation (MAPNAV_LEARNED).
#include <iosfwd>
#include <string>
#include <vector>

#include "mapnav/learned/train_segmentation.h"
#include "mapnav/vision/segmentation_eval.h"

namespace mapnav::cli {

struct TrainSegmentationConfig {
  std::string images, labels;  ///< folders; a photo's label is the PNG of the same stem (optional with logs)
  std::vector<std::string> logs;  ///< replay logs: their frames with ground-truth road masks (mapnav simulate)
  int log_stride = 5;          ///< every n-th frame of each log (consecutive frames are nearly the same picture)
  LabelClasses classes;
  std::string camera;          ///< optional camera file (where it sees the ground); default: the assumed pin-hole
  SegmentationTrainOptions options;
  std::string output;          ///< the model file, written atomically
  std::string command;         ///< the command line, recorded in the model
  bool json = false;
};

int runTrainSegmentation(const TrainSegmentationConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
