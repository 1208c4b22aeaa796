#pragma once
// Scoring a road segmentation against per-pixel labels, as the KITTI road benchmark and CamVid do
// (docs/eval.md): IoU accumulated over a set, per-image IoU, precision, recall, and — for a
// per-pixel confidence — MaxF (the F1 at the best threshold) and AP (11-point interpolated average
// precision, as the KITTI road devkit computes it). Pure counting on plain Images; no OpenCV here.
#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "mapnav/geometry/camera.h"
#include "mapnav/core/option_table.h"
#include "mapnav/geometry/types.h"
#include "mapnav/image/image.h"

namespace mapnav {

/// Which label values are road and which are left out of the scores; every other value is non-road.
struct LabelClasses {
  std::vector<int> road = {3};     ///< e.g. CamVid 3 road, 4 pavement
  std::vector<int> ignore = {};    ///< e.g. CamVid 11 unlabelled

  /// Throws InvalidInput naming the field: road empty, a value outside 0..255, or in both lists.
  void validate() const;
};

/// Pixel counts of one image (or a set, summed). Ignored pixels are in none of them.
struct PixelCounts {
  std::uint64_t tp = 0, fp = 0, fn = 0, tn = 0;

  PixelCounts& operator+=(const PixelCounts& o);
  /// TP / (TP + FP + FN); nothing when that is 0 / 0 (no road labelled and none predicted).
  std::optional<double> iou() const;
  /// TP / (TP + FP); nothing when nothing is predicted road.
  std::optional<double> precision() const;
  /// TP / (TP + FN); nothing when nothing is labelled road.
  std::optional<double> recall() const;
};

/// Which pixels are scored, as row-major pixel indices (v · width + u); a pixel listed twice counts
/// twice. The scores below take every pixel once when given none (image space); a bird's-eye grid
/// gives one sample per ground cell, the pixel its centre projects to (bev_eval.h), so the same
/// counting scores either space.
using PixelSamples = std::vector<std::uint32_t>;

/// `predicted`: 1 channel, non-zero = road. `label`: 1 channel class indices. Throws InvalidInput
/// when either is not 1 channel, their sizes differ, or a sample lies outside the image.
PixelCounts countPixels(const Image& predicted, const Image& label, const LabelClasses& classes,
                        const PixelSamples* samples = nullptr);

/// Road-pixel scores for a confidence: for each 8-bit score level s, how many labelled-road and
/// labelled-non-road pixels have that score (ignored pixels left out). A pixel is predicted road at
/// threshold t when its score ≥ t, t = 1..255.
struct ScoreHistogram {
  std::vector<std::uint64_t> road = std::vector<std::uint64_t>(256, 0);
  std::vector<std::uint64_t> non_road = std::vector<std::uint64_t>(256, 0);

  /// Adds one image (its `samples`, or every pixel). `score`: 1 channel, 0..255 (255 = surely road).
  /// Same checks as countPixels.
  void add(const Image& score, const Image& label, const LabelClasses& classes, const PixelSamples* samples = nullptr);
  /// The counts at threshold t (1..255).
  PixelCounts at(int t) const;
  /// max over t of F1 = 2PR / (P + R); nothing when no pixel is labelled road.
  std::optional<double> maxF() const;
  /// KITTI's AP: the mean over recall levels r = 0, 0.1, ..., 1 of the best precision at a threshold
  /// whose recall is ≥ r (0 when none reaches r); nothing when no pixel is labelled road.
  std::optional<double> averagePrecision() const;
};

/// The figures of a set.
struct SegmentationScores {
  int images = 0;
  PixelCounts total;                     ///< summed over the images
  std::optional<double> iou;             ///< total.iou()
  std::optional<double> iou_median;      ///< per-image IoU, median (images where it is defined)
  std::optional<double> iou_worst;       ///< per-image IoU, lowest
  std::optional<double> precision, recall;
  std::optional<double> maxf, ap;        ///< only with a per-pixel confidence
};

/// Summarises per-image counts (and the confidence histogram, when the pipeline gives one).
SegmentationScores summarize(const std::vector<PixelCounts>& per_image, const ScoreHistogram* scores = nullptr);

/// The photo with true positives green, false positives red and false negatives blue blended in
/// (half and half); ignored pixels darkened to a third; true negatives as they are. `photo` RGB,
/// the others as for countPixels.
Image drawSegmentationOverlay(const Image& photo, const Image& predicted, const Image& label,
                              const LabelClasses& classes);

/// The bootstrap region of `mapnav eval segmentation`: a trapezoid centred at the bottom of the
/// image, given as fractions of the image (the defaults are docs/eval.md's).
struct TrapezoidOptions {
  double bottom_width = 0.5;  ///< bottom edge's width, fraction of the image width. (0, 1]
  double top_width = 0.2;     ///< top edge's width, fraction of the image width. (0, bottom_width]
  double top = 0.7;           ///< top edge's row, fraction of the height from the top. [0, bottom)
  double bottom = 0.98;       ///< bottom edge's row, fraction of the height from the top. (top, 1]

  /// trapezoidOptionTable()'s rules: throws InvalidInput naming the first bad field.
  void validate() const;
};
/// Its table: each option's name (the member's), rule and description.
const OptionTable<TrapezoidOptions>& trapezoidOptionTable();
/// Its corners in pixels (u right, v down), counter-clockwise on the screen: bottom left, bottom
/// right, top right, top left.
Polygon2 bottomTrapezoid(int width, int height, const TrapezoidOptions& options = {});

/// The pin-hole assumed for photos without a camera file (`mapnav eval`, `mapnav train`): fx = fy =
/// 0.9 × width (a 58° horizontal field), principal point at the centre, 1.3 m above the ground,
/// level (the horizon at mid-height: the ground is the rows below it).
std::unique_ptr<Camera> assumedPhotoCamera(int width, int height);

/// The outline (pixel centres) of the largest 8-connected region of non-zero pixels of a 1-channel
/// mask, holes ignored; empty when the mask is empty.
Polygon2 largestRegionOutline(const Image& mask);

/// 1 channel, 255 where the label's value is road, else 0.
Image roadMask(const Image& label, const LabelClasses& classes);

}  // namespace mapnav
