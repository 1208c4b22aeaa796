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
  /// Augmentation, per photo and epoch, seeded, on top of a flip half the time and a brightness
  /// gain of 0.75-1.25 with a ±6 % tint per channel, so that the network learns the road from
  /// what holds beyond its training photos: another camera's colours and contrast, a grey camera,
  /// a blurred or noisy one, another focal length. Each in its order:
  /// the fraction of photos turned grey (luminance 0.299 R + 0.587 G + 0.114 B in every channel).
  /// 0.3: a grey camera's frames are common on small robots; the rest stay colour. In [0, 1].
  double grey_fraction = 0.3;
  /// The contrast about the photo's mean is scaled by 1 ± up to this. 0.3. In [0, 0.9].
  double contrast = 0.3;
  /// The fraction of photos blurred (3 × 3 box, an out-of-focus or smaller camera's). 0.3. In [0, 1].
  double blur_fraction = 0.3;
  /// Gaussian noise of a sigma drawn from [0, this] levels per photo. 6: a small sensor's. In [0, 64].
  double noise_levels = 6;
  /// The photo zoomed by up to this (a random window of 1 / zoom of its sides, resized back, labels
  /// and ground with it: a longer lens) half the time; 1 = never. 1.25. In [1, 2].
  double zoom = 1.25;

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
