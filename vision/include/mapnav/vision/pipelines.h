#pragma once
// The built-in vision pipelines:
//   "sidewalk"  normalised-rg Gaussian classifier + region reproduction + line labelling (the default)
//   "color-rgb" the same with an RGB classifier (3.4, before 3.4.3)
//   "blue-band" a threshold on the blue channel (3.6.3, the Warp runs), region + labelling
// and the options of these three region pipelines: a struct each, whose member initialisers are the
// defaults, described by an option table (core/option_table.h) that configure() reads the JSON
// options with and listPipelines() lists (PipelineInfo::options, `mapnav pipelines`). The
// "cluster-perceptron" and "edge-tracker" pipelines' options are in cluster_perceptron.h and
// edge_tracker.h. ScorePipeline: the region steps around a per-pixel probability of one's own
// (the "learned" pipeline, learned/).
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/vision/color_classifier.h"
#include "mapnav/vision/line_labelling.h"
#include "mapnav/vision/region.h"
#include "mapnav/vision_iface/pipeline.h"

namespace mapnav {

/// Registers the built-in pipelines (idempotent).
void registerBuiltinPipelines();

/// The default pipeline's name: "sidewalk".
inline constexpr const char* kDefaultPipeline = "sidewalk";

/// What every region pipeline has: the frame's checks, the road score's smoothing, region
/// reproduction (Wallace 1985, 2.2.1), the polygon's lines and their labels (2.2.2), and the grid.
/// Lengths in pixels are at full resolution (divided by grid_px on the grid) of a frame of
/// kReferenceFramePixels (480 × 360): on a smaller frame each length in pixels, grid_px and
/// label_erosion_px included, is multiplied by pixelScale() and min_predicted_px by its square, so
/// that one default serves a 240 × 180 camera and a 1280 × 720 one (a larger frame keeps them). The
/// classifier's min_training_pixels is a count of samples for its Gaussians, not a share of the
/// frame, and stays.
struct RegionPipelineOptions {
  double dark_level = 20;             ///< ground mean grey (0-255) below which: "frame too dark"
  double saturated_level = 250;       ///< a pixel is saturated when all its channels reach this
  double overexposed_fraction = 0.5;  ///< saturated ground fraction above which: "frame over-exposed"
  int min_predicted_px = 500;         ///< fewer predicted road pixels in view: "nothing predicted in view"
  double min_region_fraction = 0.15;  ///< region / predicted road area below which: "no road-coloured region"
  int smooth_px = 2;                  ///< box-filter radius on the per-pixel road score
  /// Region reproduction: blocks, morphology, holes, parts (its `reference` is this struct's).
  RegionOptions region;
  double region_tolerance_px = 0.75;  ///< polygon tolerance of the region outline (region_image)
  /// The polygon's lines and their labels; `min_length_px` is the JSON's "min_line_length_px" (its
  /// `reference` is this struct's).
  LineOptions lines;
  /// Classify and reproduce the region on cells of grid_px x grid_px pixels (the frame averaged over
  /// each); 1 = every pixel. 2 runs the loop ~2.6 times faster with the same localisation.
  int grid_px = 2;
  /// Every pixel with the reference implementations (double precision, OpenCV, CGAL): grid_px 1's
  /// answers, several times slower; for tests and benchmarks.
  bool reference = false;

  /// Throws InvalidInput "RegionPipelineOptions::FIELD = VALUE: must be ..." for a field out of its range.
  void validate() const;
};

/// "sidewalk" and "color-rgb": one Gaussian road class per surface in view against a non-road
/// class, trained from the prediction each frame (ColorClassifier).
struct ColorPipelineOptions : RegionPipelineOptions {
  bool adaptive = true;               ///< keep the models from frame to frame, blending in each frame's
  /// Each surface's classes. The pipeline's defaults, tuned on frames and photos, where they are not
  /// the classifier's: the space is the pipeline's ("sidewalk": normalised rg, "color-rgb": log RGB);
  /// `min_pixels` is the JSON's "min_training_pixels" (labelled training cells). Its `space` and
  /// `stride` are the pipeline's to set (the pipeline gathers the training cells itself).
  ColorClassifierOptions classifier = {.nonroad_gate_sigma = 8, .brightness_sigma = 0.1, .brightness_separation = 5,
                                       .noise_sigma = 3};
  int label_erosion_px = 6;           ///< training labels: the predicted road and the rest eroded by this
  double nonroad_gate_sigma_mapped = 3;  ///< classifier.nonroad_gate_sigma where the prediction comes from a pose estimate (a mission)
  double outlier_llr = 6;             ///< adaptive: drop training pixels the model contradicts by more log-odds
  double llr_threshold = 0;           ///< road where the smoothed log-odds exceed this
  double min_separation = 0.5;        ///< Bhattacharyya distance of the classes below which: "no road-coloured region"

  /// Throws InvalidInput "ColorPipelineOptions::FIELD = VALUE: must be ..." for a field out of its range.
  void validate() const;
};

/// "blue-band": road on one side of a threshold on the blue channel (Wallace 1985, 3.6.3).
struct BlueBandOptions : RegionPipelineOptions {
  /// The blue level between road and non-road; road is on the side where most of the predicted road
  /// is (bright against grass, dark against pavements and walls). -1 = Otsu's threshold on the ground.
  double threshold = -1;
  /// > 0: road is instead the band of blue levels within this many sigma of the predicted road's
  /// median (sigma: half the spread between its 16th and 84th percentiles, at least 2 levels);
  /// `threshold` is then unused. 0 = one cut at `threshold`.
  double band_sigma = 4;

  /// Throws InvalidInput "BlueBandOptions::FIELD = VALUE: must be ..." for a field out of its range.
  void validate() const;
};

/// Pipelines that score every pixel themselves (a learned network: learned/): road where the
/// probability, smoothed over the (2 smooth_px + 1)² box, exceeds `threshold`.
struct ScorePipelineOptions : RegionPipelineOptions {
  double threshold = 0.5;  ///< road where the smoothed road probability exceeds this, in (0, 1)
  /// The centre line of the road ahead from the region (regionCentreLine, vision/centre_line.h), so
  /// that the Map module can steer by it where no road edge is labelled. Default true.
  bool centre_line = true;

  /// Throws InvalidInput "ScorePipelineOptions::FIELD = VALUE: must be ..." for a field out of its range.
  void validate() const;
};

/// A region pipeline whose per-pixel road probability comes from a subclass (e.g. a network): the
/// frame checks, region reproduction, polygon, lines and their labels, the mask and the confidence
/// (the probability on 0..255) are every region pipeline's. The prediction picks which road
/// region is the road and labels the lines; a subclass may learn from it (learnFrom).
class ScorePipeline : public VisionPipeline {
 public:
  explicit ScorePipeline(std::string name);
  ~ScorePipeline() override;
  std::string name() const override;
  DetectedObject detect(const VisionFrame& frame, const PredictedObject& prediction) override;
  void reset() override {}

 protected:
  /// P(road) of each pixel of `rgb` (width × height × 3, row-major), width × height values in [0, 1].
  /// The frame is the pipeline's grid (grid_px: each cell the mean of its pixels); `ground`: 1 where
  /// the cell sees the ground, else 0 (width × height).
  virtual std::vector<float> roadProbability(const std::uint8_t* rgb, int width, int height,
                                             const std::uint8_t* ground) = 0;
  /// Called after roadProbability() on every frame with a prediction, with what it answered and the
  /// predicted road on the same grid (1 channel, non-zero = road): a subclass that learns online
  /// (the learned pipeline's `adapt`) learns from them for the next frames. Default: nothing.
  virtual void learnFrom(const std::uint8_t* rgb, int width, int height, const std::uint8_t* ground,
                         const std::vector<float>& probability, const std::uint8_t* predicted) {
    (void)rgb, (void)width, (void)height, (void)ground, (void)probability, (void)predicted;
  }
  /// The options of the region steps and the threshold (the subclass's struct).
  virtual const ScorePipelineOptions& scoreOptions() const = 0;

 private:
  class Impl;
  std::unique_ptr<Impl> impl_;
};

/// The options' tables: names, ranges and the descriptions `mapnav pipelines` shows.
const OptionTable<ScorePipelineOptions>& scorePipelineOptionTable();
const OptionTable<RegionPipelineOptions>& regionPipelineOptionTable();
const OptionTable<ColorPipelineOptions>& colorPipelineOptionTable();
const OptionTable<BlueBandOptions>& blueBandOptionTable();

}  // namespace mapnav
