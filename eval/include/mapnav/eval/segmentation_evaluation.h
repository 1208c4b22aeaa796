#pragma once
// A vision pipeline evaluated on labelled photos (docs/eval.md), as `mapnav eval segmentation` and
// Python's evaluate_segmentation run it: the photos and their labels read and checked
// (labelled_photos.h), one pipeline run over them in file-name order from a bootstrap region, its
// road scored per pixel or in a bird's-eye grid (vision/segmentation_eval.h, vision/bev_eval.h),
// the two trivial baselines scored the same way over the same photos, and the margin over the better.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/vision/bev_eval.h"
#include "mapnav/vision/segmentation_eval.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {

/// The road region the pipeline trains on, given in the image and the same for every photo.
enum class EvalBootstrap {
  Trapezoid,         ///< bottomTrapezoid() of the photos' size ("trapezoid")
  LabelsFirstFrame,  ///< the outline of the first photo's largest labelled road region ("labels-first-frame")
};
std::string_view toString(EvalBootstrap bootstrap);
/// "trapezoid" or "labels-first-frame"; throws InvalidInput naming the value and the names there are.
EvalBootstrap evalBootstrapFromString(std::string_view name);

struct SegmentationEvalOptions {
  EvalBootstrap bootstrap = EvalBootstrap::Trapezoid;  ///< the region the pipeline trains on
  TrapezoidOptions trapezoid = {};                     ///< the trapezoid bootstrap's shape (docs/eval.md's)
  /// The file of the camera that took the photos, its image their size; "" for assumedPhotoCamera()
  /// of their size (a level pin-hole 1.3 m up).
  std::string camera = {};
  /// Score in a bird's-eye grid on the ground, as the KITTI road benchmark does, instead of per pixel
  /// of the image; needs `camera` (the grid is in metres on the ground that camera sees).
  bool bev = false;
  BevGrid bev_grid = {};  ///< that grid: KITTI's by default
  /// A folder for one overlay per photo (STEM.png: TP green, FP red, FN blue; with `bev` also
  /// STEM.bev.png in the grid), written once every photo is scored; "" for none.
  std::string overlays = {};
  /// Score the photos at this size instead of their own, px (0 and 0: as they are): each photo
  /// resized (averaged over the pixels it shrinks from) and its labels by their nearest pixel,
  /// before anything runs; a `camera` must then be of this size. To see whether a pipeline's
  /// defaults hold on a smaller or larger camera than the photos'.
  int resize_width = 0;
  int resize_height = 0;
  /// Score the photos as a grey camera gives them (greyed(): luminance in every channel), after
  /// any resize. Default false.
  bool grey = false;

  /// segmentationEvalOptionTable()'s rules: throws InvalidInput naming the first bad field.
  void validate() const;
};
/// Its table: the trapezoid's fields as trapezoid_*, the grid's as bev_*.
const OptionTable<SegmentationEvalOptions>& segmentationEvalOptionTable();

/// One photo's result.
struct PhotoScore {
  std::string image;    ///< the photo's file name, without its folder
  PixelCounts counts;   ///< over the scored pixels or grid cells
  std::string failure;  ///< the pipeline's reason when it failed on the photo (scored as no road), else ""
};

/// The bird's-eye grid the scores were counted in, as laid on the camera's image.
struct ScoredBevGrid {
  BevGrid grid;
  int columns = 0, rows = 0;
  std::size_t cells_in_image = 0;  ///< the cells scored: those whose centre projects into the image
};

/// The figures of one evaluation: what `mapnav eval segmentation` prints.
struct SegmentationEvaluation {
  std::string pipeline;                                ///< its name()
  EvalBootstrap bootstrap = EvalBootstrap::Trapezoid;
  std::optional<ScoredBevGrid> bev;                    ///< the grid when scored in one; nothing: per pixel
  std::vector<PhotoScore> photos;                      ///< in file-name order
  /// Over the set. MaxF and AP from the per-pixel road confidence (a failed photo's is 0
  /// everywhere); nothing when no photo gave one rather than made up from the binary region.
  SegmentationScores scores;
  bool confidence_given = false;                       ///< some photo gave a per-pixel road confidence
  SegmentationScores baseline_horizon;                 ///< every pixel whose ray meets the ground is road
  SegmentationScores baseline_bootstrap;               ///< the bootstrap region alone is road
  /// scores.iou − the better baseline's IoU; nothing when one of them is undefined.
  std::optional<double> margin;
  int failed = 0;                                      ///< photos on which the pipeline failed
};

/// Runs `pipeline` as it is (an adaptive one carries what it learns from photo to photo, and from
/// earlier calls: reset() it for a fresh start) over the photos of `images` with their labels in
/// `labels` (readLabelledPhotos, all of one size), each with the bootstrap region as its prediction,
/// and scores its road region (its per-pixel road_mask, holes and all, else its outline filled)
/// against the labels as `classes` reads them. Everything is read and checked before the pipeline
/// runs, and the overlays are written only once every photo is scored. Throws InvalidInput for bad
/// options or input (naming the file: a camera whose image is not the photos' size, a first label
/// without road for labels-first-frame), IoError for a folder or file that cannot be read or written.
SegmentationEvaluation evaluateSegmentation(VisionPipeline& pipeline, const std::filesystem::path& images,
                                            const std::filesystem::path& labels, const LabelClasses& classes,
                                            const SegmentationEvalOptions& options = {});

/// The evaluation as `mapnav eval segmentation --json` prints it (docs/eval.md): {"pipeline",
/// "bootstrap", "space", "bev", "images", "failed", "iou", "iou_median", "iou_worst", "precision",
/// "recall", "maxf", "ap", "baseline_horizon_iou", "baseline_bootstrap_iou", "margin", "per_image":
/// [{"image", "iou", "failed"}]}, figures to 4 decimals, null when undefined; indented, with a final newline.
std::string evaluationJson(const SegmentationEvaluation& evaluation);

}  // namespace mapnav
