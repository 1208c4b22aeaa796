// The training options' table (train_segmentation.h). Without Torch, in a library of its own
// (mapnav_learned_options): the CLI checks a training's options before it opens the learned module.
#include "mapnav/learned/train_segmentation.h"

namespace mapnav {

const OptionTable<SegmentationTrainOptions>& segmentationTrainOptionTable() {
  using O = SegmentationTrainOptions;
  static const OptionTable<O> table =
      OptionTable<O>("SegmentationTrainOptions")
          .field("epochs", &O::epochs, inRange(1, 100000), "passes over the training photos")
          .field("seed", &O::seed, "initial weights, order, flips and colour jitter")
          .field("width", &O::width, inRange(8, 4096), "the network's input width, pixels")
          .field("height", &O::height, inRange(8, 4096), "... and height, pixels")
          .field("batch", &O::batch, inRange(1, 1024), "photos per step")
          .field("learning_rate", &O::learning_rate, aboveUpTo(0, 1),
                 "Adam's, halved at 60 % and again at 85 % of the epochs")
          .field("validation_fraction", &O::validation_fraction, inRange(0, 0.5),
                 "every round(1 / this)-th photo is held apart for the validation IoU; 0 = none")
          .field("threads", &O::threads, inRange(0, 256), "Torch's CPU threads");
  return table;
}

void SegmentationTrainOptions::validate() const { segmentationTrainOptionTable().validate(*this); }

}  // namespace mapnav
