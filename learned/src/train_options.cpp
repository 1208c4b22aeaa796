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
          .field("threads", &O::threads, inRange(0, 256), "Torch's CPU threads")
          .field("grey_fraction", &O::grey_fraction, inRange(0, 1), "augmentation: the fraction of photos turned grey")
          .field("contrast", &O::contrast, inRange(0, 0.9), "... the contrast scaled by 1 +- up to this")
          .field("blur_fraction", &O::blur_fraction, inRange(0, 1), "... the fraction of photos blurred (3 x 3 box)")
          .field("noise_levels", &O::noise_levels, inRange(0, 64), "... Gaussian noise of a sigma up to this, levels")
          .field("zoom", &O::zoom, inRange(1, 2), "... zoomed by up to this half the time (1: never)");
  return table;
}

void SegmentationTrainOptions::validate() const { segmentationTrainOptionTable().validate(*this); }

}  // namespace mapnav
