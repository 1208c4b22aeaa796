#pragma once
// What the learned network trains on, read and checked, and the training run: `mapnav train
// segmentation` and Python's train_segmentation call trainSegmentationModel. Torch stays out: the
// training itself is the learned module's (learned_api.h), opened when it is called.
#include <functional>
#include <string>
#include <vector>

#include "mapnav/learned/learned_api.h"
#include "mapnav/learned/train_segmentation.h"
#include "mapnav/vision/segmentation_eval.h"

namespace mapnav {

/// Labelled photos and simulator logs to train on; either or both.
struct TrainingSet {
  std::string images, labels;     ///< folders; a photo's label is the PNG of the same stem (both or neither)
  std::vector<std::string> logs;  ///< replay logs of mapnav simulate: their frames and ground-truth road masks
  int log_stride = 5;             ///< every n-th frame of each log (consecutive frames are nearly the same picture)
  LabelClasses classes;           ///< which label values are road, which are left out of the loss
  std::string camera;             ///< camera file of the photos; "" = the assumed level pin-hole (docs/eval.md)

  /// Throws InvalidInput naming the field: nothing to train on, only one of images and labels,
  /// log_stride < 1, bad classes.
  void validate() const;
};

/// The set's photos as the trainer wants them (label 1 road, 255 left out, 0 the rest; the camera's
/// ground mask), photos first in file-name order, then each log's frames. Throws as
/// readLabelledPhotos and ReplayLog::open; InvalidInput naming the photo whose size is not the
/// camera's, and the log with no ground-truth mask.
std::vector<TrainingPhoto> readTrainingPhotos(const TrainingSet& set);

/// The set read, the network trained with `options` (validated first, before the learned module
/// opens) and written atomically to `output`, `command` recorded in it. Throws as
/// readTrainingPhotos, trainSegmentation and learnedModule() (NotFound when the build has none).
TrainedModelSummary trainSegmentationModel(const TrainingSet& set, const SegmentationTrainOptions& options,
                                           const std::function<void(const EpochReport&)>& progress,
                                           const std::string& command, const std::string& output);

/// The summary as `mapnav train segmentation --json` prints it (2-space JSON, a newline at the end).
std::string trainedModelJson(const std::string& output, const TrainedModelSummary& model);

}  // namespace mapnav
