#pragma once
// Training a SegmentationModel on labelled photos (docs/learned.md): Adam on the per-pixel binary
// cross-entropy, with ignored pixels left out, flips and colour jitter drawn from the seed. Same
// photos, options and seed, same model bytes (on one build, with the same `threads`).
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/image/image.h"
#include "mapnav/learned/segmentation_model.h"

namespace mapnav {

/// One training photo: its colours, its road label and where its camera sees the ground.
struct TrainingPhoto {
  std::string name;   ///< for messages (the file)
  Image rgb;          ///< 3 channels
  Image road;         ///< 1 channel, same size: 1 road, 0 not road, 255 left out of the loss and the scores
  Image ground;       ///< 1 channel, same size: non-zero where the camera sees the ground
};

struct SegmentationTrainOptions {
  int epochs = 60;                 ///< passes over the training photos
  std::uint64_t seed = 1;          ///< initial weights, order, flips and colour jitter
  int width = 240, height = 180;   ///< the network's input size, pixels (multiples of 8 keep every level aligned)
  int batch = 8;                   ///< photos per step
  double learning_rate = 3e-3;     ///< Adam's, halved at 60 % and again at 85 % of the epochs
  /// Every round(1 / this)-th photo is held apart for the validation IoU (at least one of two or more
  /// photos); 0 = none.
  double validation_fraction = 0.1;
  int threads = 2;                 ///< Torch's CPU threads (the answer is deterministic for a given count)

  /// Throws InvalidInput "SegmentationTrainOptions::FIELD = VALUE: must be ..." for a field out of range.
  /// (In mapnav_learned_options, without Torch, so that a program that opens learned/ only when it
  /// trains checks its options first.)
  void validate() const;
};

/// The options' names, rules and descriptions; validate() checks them.
const OptionTable<SegmentationTrainOptions>& segmentationTrainOptionTable();

/// One epoch's figures, for a progress bar.
struct EpochReport {
  int epoch = 0, epochs = 0;
  double loss = 0;                       ///< mean training loss
  std::optional<double> validation_iou;  ///< on the held-apart photos
};

/// Trains a fresh model on `photos`. Throws InvalidInput when a photo's images disagree in size or
/// channels, or too few photos are left to train on. `progress` is called after every epoch.
SegmentationModel trainSegmentation(const std::vector<TrainingPhoto>& photos, const SegmentationTrainOptions& options,
                                    const std::function<void(const EpochReport&)>& progress = {},
                                    const std::string& command = {});

/// Road IoU (P > 0.5 inside the ground, ignored pixels left out) of `model` over `photos`; nothing when
/// no pixel is road in either.
std::optional<double> segmentationIou(const SegmentationModel& model, const std::vector<TrainingPhoto>& photos);

}  // namespace mapnav
