#include "mapnav/eval/segmentation_evaluation.h"

#include <algorithm>
#include <memory>
#include <sstream>
#include <string>
#include <utility>

#include "mapnav/core/error.h"
#include "mapnav/core/interrupt.h"
#include "mapnav/eval/labelled_photos.h"
#include "mapnav/image/png.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/mission/image_region.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision/resize.h"

namespace mapnav {

namespace fs = std::filesystem;

std::string_view toString(EvalBootstrap bootstrap) {
  return bootstrap == EvalBootstrap::Trapezoid ? "trapezoid" : "labels-first-frame";
}

EvalBootstrap evalBootstrapFromString(std::string_view name) {
  if (name == "trapezoid") return EvalBootstrap::Trapezoid;
  if (name == "labels-first-frame") return EvalBootstrap::LabelsFirstFrame;
  throw InvalidInput("bootstrap \"" + std::string(name) + "\": expected trapezoid or labels-first-frame");
}

const OptionTable<SegmentationEvalOptions>& segmentationEvalOptionTable() {
  using O = SegmentationEvalOptions;
  static const OptionTable<O> table =
      OptionTable<O>("SegmentationEvalOptions")
          .choice("bootstrap", &O::bootstrap,
                  {{EvalBootstrap::Trapezoid, "trapezoid"}, {EvalBootstrap::LabelsFirstFrame, "labels-first-frame"}},
                  "the road region the pipeline trains on: the bottom-centre trapezoid, or the first photo's largest "
                  "labelled road region")
          .nest(&O::trapezoid, trapezoidOptionTable(),
                {{"bottom_width", "trapezoid_bottom_width"}, {"top_width", "trapezoid_top_width"},
                 {"top", "trapezoid_top"}, {"bottom", "trapezoid_bottom"}})
          .field("camera", &O::camera,
                 "the file of the camera that took the photos, its image their size; \"\": a level pin-hole of their "
                 "size, fx = fy = 0.9 width, 1.3 m up")
          .field("bev", &O::bev, "score in a bird's-eye grid on the ground (KITTI road benchmark) instead of per pixel")
          .nest(&O::bev_grid, bevGridOptionTable(),
                {{"x_min_m", "bev_x_min_m"}, {"x_max_m", "bev_x_max_m"}, {"z_min_m", "bev_z_min_m"},
                 {"z_max_m", "bev_z_max_m"}, {"cell_m", "bev_cell_m"}})
          .field("overlays", &O::overlays, "a folder for one TP/FP/FN overlay per photo; \"\": none")
          .field("resize_width", &O::resize_width, inRange(0, 8192),
                 "score the photos resized to this width, px (0: their own size)")
          .field("resize_height", &O::resize_height, inRange(0, 8192), "... and this height, px (0: their own size)")
          .field("grey", &O::grey, "score the photos as a grey camera gives them (luminance in every channel)")
          .check("resize_height", [](const O& o) { return (o.resize_width > 0) == (o.resize_height > 0); },
                 "0 exactly when resize_width is 0 (a size needs both)")
          .check("bev", [](const O& o) { return !o.bev || !o.camera.empty(); },
                 "false without a camera (the grid is in metres on the ground the camera sees)");
  return table;
}

void SegmentationEvalOptions::validate() const { segmentationEvalOptionTable().validate(*this); }

namespace {

// What the pipeline did on each photo, counted over the scored samples.
struct Run {
  std::vector<PixelCounts> counts;
  std::vector<std::string> failures;  // per photo, empty when the pipeline found a region
  std::vector<Image> overlays;        // image space, when asked for
  ScoreHistogram histogram;           // from the per-pixel confidence; a failed photo's is 0 everywhere
  bool confidence_given = false;
};

Run runPipeline(VisionPipeline& pipeline, const std::vector<LabelledPhoto>& set, const Camera& camera,
                const Prediction& prediction, const LabelClasses& classes, const PixelSamples* samples,
                bool overlays) {
  const int w = camera.width(), h = camera.height();
  const Image no_confidence(w, h, 1);
  Run run;
  for (const LabelledPhoto& s : set) {
    throwIfInterrupted();  // Ctrl-C: stop before the overlays are written
    VisionFrame frame{w, h, s.image.data.data(), &camera, 0.0};
    frame.want_masks = true;
    const DetectedObject d = pipeline.detect(frame, prediction.view);
    const bool ok = d.status == DetectedObject::Status::Ok;
    const Image mask = ok ? regionMask(d, w, h) : Image(w, h, 1);
    run.counts.push_back(countPixels(mask, s.label, classes, samples));
    run.failures.push_back(ok ? "" : d.reason);
    run.confidence_given = run.confidence_given || !d.road_confidence.empty();
    run.histogram.add(d.road_confidence.empty() ? no_confidence : d.road_confidence, s.label, classes, samples);
    if (overlays) run.overlays.push_back(drawSegmentationOverlay(s.image, mask, s.label, classes));
  }
  return run;
}

// The two trivial answers the pipeline must beat, scored like it over the same photos and samples.
void scoreBaselines(const std::vector<LabelledPhoto>& set, const Camera& camera, const Polygon2& bootstrap,
                    const LabelClasses& classes, const PixelSamples* samples, SegmentationEvaluation& out) {
  const Image horizon = groundMask(camera);
  const Image region = regionMask(bootstrap, camera.width(), camera.height());
  std::vector<PixelCounts> horizon_counts, region_counts;
  for (const LabelledPhoto& s : set) {
    horizon_counts.push_back(countPixels(horizon, s.label, classes, samples));
    region_counts.push_back(countPixels(region, s.label, classes, samples));
  }
  out.baseline_horizon = summarize(horizon_counts);
  out.baseline_bootstrap = summarize(region_counts);
}

// The pipeline's IoU less the better baseline's; nothing when any is undefined.
std::optional<double> marginOver(const SegmentationEvaluation& e) {
  if (!e.scores.iou || !e.baseline_horizon.iou || !e.baseline_bootstrap.iou) return std::nullopt;
  return *e.scores.iou - std::max(*e.baseline_horizon.iou, *e.baseline_bootstrap.iou);
}

std::unique_ptr<Camera> photoCamera(const SegmentationEvalOptions& options, int w, int h) {
  std::unique_ptr<Camera> camera = options.camera.empty() ? assumedPhotoCamera(w, h) : loadCamera(options.camera);
  if (camera->width() != w || camera->height() != h)
    throw InvalidInput(options.camera + ": the camera's image is " + std::to_string(camera->width()) + "x" +
                       std::to_string(camera->height()) + " but the photos are " + std::to_string(w) + "x" +
                       std::to_string(h));
  return camera;
}

std::optional<BevSampling> gridSampling(const SegmentationEvalOptions& options, const Camera& camera) {
  if (!options.bev) return std::nullopt;
  BevSampling bev = bevSampling(camera, options.bev_grid);
  if (bev.samples.empty()) {
    const BevGrid& g = options.bev_grid;
    std::ostringstream text;
    text << options.camera << ": no cell of the grid (x " << g.x_min_m << ".." << g.x_max_m << " m, z " << g.z_min_m
         << ".." << g.z_max_m << " m) projects into the image of the camera";
    throw InvalidInput(text.str());
  }
  return bev;
}

Polygon2 bootstrapRegion(const SegmentationEvalOptions& options, const LabelledPhoto& first,
                         const LabelClasses& classes) {
  const int w = first.image.width, h = first.image.height;
  const Polygon2 region = options.bootstrap == EvalBootstrap::Trapezoid
                              ? bottomTrapezoid(w, h, options.trapezoid)
                              : largestRegionOutline(roadMask(first.label, classes));
  if (region.size() < 3) throw InvalidInput(first.label_file.string() + ": no road labelled to bootstrap from");
  return region;
}

// The overlays, and in a grid each also resampled into it (STEM.bev.png).
void writeOverlays(const SegmentationEvalOptions& options, const std::vector<LabelledPhoto>& set, const Run& run,
                   const std::optional<BevSampling>& bev) {
  if (options.overlays.empty()) return;
  fs::create_directories(options.overlays);
  for (std::size_t i = 0; i < set.size(); ++i) {
    const std::string stem = set[i].image_file.stem().string();
    writePng(run.overlays[i], fs::path(options.overlays) / (stem + ".png"));
    if (bev) writePng(resampleToBev(run.overlays[i], *bev), fs::path(options.overlays) / (stem + ".bev.png"));
  }
}

}  // namespace

SegmentationEvaluation evaluateSegmentation(VisionPipeline& pipeline, const fs::path& images, const fs::path& labels,
                                            const LabelClasses& classes, const SegmentationEvalOptions& options) {
  classes.validate();
  options.validate();
  std::vector<LabelledPhoto> set = readLabelledPhotos(images, labels, true);
  if (options.resize_width > 0) {
    const ImageSize size{options.resize_width, options.resize_height};
    for (LabelledPhoto& p : set) {
      p.image = resized(p.image, size, ResizeKind::Photo);
      p.label = resized(p.label, size, ResizeKind::Labels);
    }
  }
  if (options.grey)
    for (LabelledPhoto& p : set) p.image = greyed(p.image);
  const std::unique_ptr<Camera> camera = photoCamera(options, set.front().image.width, set.front().image.height);
  const std::optional<BevSampling> bev = gridSampling(options, *camera);
  const PixelSamples* samples = bev ? &bev->samples : nullptr;
  const Polygon2 bootstrap = bootstrapRegion(options, set.front(), classes);
  const Run run = runPipeline(pipeline, set, *camera, predictionFromImageRegion(bootstrap, *camera), classes, samples,
                              !options.overlays.empty());

  SegmentationEvaluation e;
  e.pipeline = pipeline.name();
  e.bootstrap = options.bootstrap;
  if (bev) e.bev = ScoredBevGrid{options.bev_grid, bev->columns, bev->rows, bev->samples.size()};
  for (std::size_t i = 0; i < set.size(); ++i)
    e.photos.push_back({set[i].image_file.filename().string(), run.counts[i], run.failures[i]});
  e.confidence_given = run.confidence_given;
  e.scores = summarize(run.counts, run.confidence_given ? &run.histogram : nullptr);
  scoreBaselines(set, *camera, bootstrap, classes, samples, e);
  e.margin = marginOver(e);
  e.failed = static_cast<int>(
      std::count_if(run.failures.begin(), run.failures.end(), [](const std::string& f) { return !f.empty(); }));
  writeOverlays(options, set, run, bev);
  return e;
}

}  // namespace mapnav
