#include "eval_command.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <map>
#include <optional>
#include <ostream>
#include <sstream>

#include "cli.h"
#include "command_line.h"
#include "command_support.h"
#include "json_numbers.h"
#include "labelled_photos.h"
#include "mapnav/core/error.h"
#include "mapnav/core/interrupt.h"
#include "mapnav/core/json.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/image/png.h"
#include "mapnav/mission/image_region.h"
#include "mapnav/vision/bev_eval.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision_iface/pipeline.h"
#include "pipelines_command.h"

namespace mapnav::cli {

namespace fs = std::filesystem;

namespace {

using Sample = LabelledPhoto;

std::vector<Sample> readSet(const EvalSegmentationConfig& config) {
  return readLabelledPhotos(config.images, config.labels, true);
}

/// A score in the JSON and in the text: 4 decimals, null when undefined.
Json number(const std::optional<double>& v) { return roundedOrNull(v, 4); }
std::string scoreOrNull(const std::optional<double>& v) { return fixedOr(v, 4, "null"); }

// The two trivial answers the pipeline must beat, scored like it over the same photos (and the
// same samples: every pixel, or one per bird's-eye cell).
struct Baselines {
  SegmentationScores horizon;    ///< every pixel below the horizon is road
  SegmentationScores bootstrap;  ///< the bootstrap region alone is road
};

Baselines scoreBaselines(const std::vector<Sample>& set, const Camera& camera, const Polygon2& bootstrap,
                         const LabelClasses& classes, const PixelSamples* samples) {
  const Image horizon = groundMask(camera);
  const Image region = regionMask(bootstrap, camera.width(), camera.height());
  std::vector<PixelCounts> horizon_counts, region_counts;
  for (const Sample& s : set) {
    horizon_counts.push_back(countPixels(horizon, s.label, classes, samples));
    region_counts.push_back(countPixels(region, s.label, classes, samples));
  }
  return {summarize(horizon_counts), summarize(region_counts)};
}

// The pipeline's IoU less the better baseline's; nothing when either is undefined.
std::optional<double> marginOver(const std::optional<double>& iou, const Baselines& baselines) {
  if (!iou || !baselines.horizon.iou || !baselines.bootstrap.iou) return std::nullopt;
  return *iou - std::max(*baselines.horizon.iou, *baselines.bootstrap.iou);
}

// What the pipeline did on each photo, counted over the scored samples.
struct Run {
  std::vector<PixelCounts> counts;
  std::vector<std::string> failures;  // per image, empty when the pipeline found a region
  std::vector<Image> overlays;        // image space, when asked for
  // MaxF and AP from the pipelines' per-pixel confidence; a failed frame's is 0 everywhere. A
  // pipeline that gives none leaves them null rather than made up from the binary region.
  ScoreHistogram histogram;
  bool confidence_given = false;
};

Run runPipeline(const EvalSegmentationConfig& config, VisionPipeline& pipeline, const std::vector<Sample>& set,
                const Camera& camera, const Prediction& prediction, const PixelSamples* samples) {
  const int w = camera.width(), h = camera.height();
  const Image no_confidence(w, h, 1);
  Run run;
  for (const Sample& s : set) {
    throwIfInterrupted();  // Ctrl-C: stop before the overlays are written
    VisionFrame frame{w, h, s.image.data.data(), &camera, 0.0};
    frame.want_masks = true;
    const DetectedObject d = pipeline.detect(frame, prediction.view);
    const bool ok = d.status == DetectedObject::Status::Ok;
    const Image mask = ok ? regionMask(d, w, h) : Image(w, h, 1);
    run.counts.push_back(countPixels(mask, s.label, config.classes, samples));
    run.failures.push_back(ok ? "" : d.reason);
    run.confidence_given = run.confidence_given || !d.road_confidence.empty();
    run.histogram.add(d.road_confidence.empty() ? no_confidence : d.road_confidence, s.label, config.classes, samples);
    if (!config.overlays.empty()) run.overlays.push_back(drawSegmentationOverlay(s.image, mask, s.label, config.classes));
  }
  return run;
}

// The overlays, and with --bev each also resampled into the grid (STEM.bev.png).
void writeOverlays(const EvalSegmentationConfig& config, const std::vector<Sample>& set, const Run& run,
                   const std::optional<BevSampling>& bev) {
  if (config.overlays.empty()) return;
  fs::create_directories(config.overlays);
  for (std::size_t i = 0; i < set.size(); ++i) {
    const std::string stem = set[i].image_file.stem().string();
    writePng(run.overlays[i], fs::path(config.overlays) / (stem + ".png"));
    if (bev) writePng(resampleToBev(run.overlays[i], *bev), fs::path(config.overlays) / (stem + ".bev.png"));
  }
}

// Which space was scored, so that image and bird's-eye figures are never mistaken for each other.
Json spaceJson(const EvalSegmentationConfig& config, const std::optional<BevSampling>& bev) {
  if (!bev) return nullptr;
  const BevGrid& g = config.bev_grid;
  return {{"x_m", {g.x_min_m, g.x_max_m}}, {"z_m", {g.z_min_m, g.z_max_m}}, {"cell_m", g.cell_m},
          {"columns", bev->columns},       {"rows", bev->rows},             {"cells_in_image", bev->samples.size()}};
}

std::string spaceText(const EvalSegmentationConfig& config, const std::optional<BevSampling>& bev) {
  if (!bev) return "  scored per pixel, in the image\n";
  const BevGrid& g = config.bev_grid;
  std::ostringstream t;
  t << "  scored in a bird's-eye grid (KITTI road benchmark): x " << g.x_min_m << ".." << g.x_max_m << " m, z "
    << g.z_min_m << ".." << g.z_max_m << " m, " << g.cell_m << " m cells; " << bev->samples.size() << " of "
    << bev->columns * bev->rows << " cells in the image\n";
  return t.str();
}

struct Summary {
  SegmentationScores scores;
  Baselines baselines;
  std::optional<double> margin;
  long failed = 0;
};

void printJson(const EvalSegmentationConfig& config, const std::vector<Sample>& set, const Run& run,
               const Summary& sum, const std::optional<BevSampling>& bev, std::ostream& out) {
  Json per_image = Json::array();
  for (std::size_t i = 0; i < set.size(); ++i)
    per_image.push_back({{"image", set[i].image_file.filename().string()},
                         {"iou", number(run.counts[i].iou())},
                         {"failed", run.failures[i].empty() ? Json(nullptr) : Json(run.failures[i])}});
  const SegmentationScores& s = sum.scores;
  const Json j = {{"pipeline", config.pipeline},
                  {"bootstrap", config.bootstrap},
                  {"space", bev ? "bev" : "image"},
                  {"bev", spaceJson(config, bev)},
                  {"images", s.images},
                  {"failed", sum.failed},
                  {"iou", number(s.iou)},
                  {"iou_median", number(s.iou_median)},
                  {"iou_worst", number(s.iou_worst)},
                  {"precision", number(s.precision)},
                  {"recall", number(s.recall)},
                  {"maxf", number(s.maxf)},
                  {"ap", number(s.ap)},
                  {"baseline_horizon_iou", number(sum.baselines.horizon.iou)},
                  {"baseline_bootstrap_iou", number(sum.baselines.bootstrap.iou)},
                  {"margin", number(sum.margin)},
                  {"per_image", per_image}};
  out << dumpJson(j);
}

void printText(const EvalSegmentationConfig& config, const std::vector<Sample>& set, const Run& run,
               const Summary& sum, const std::optional<BevSampling>& bev, std::ostream& out) {
  for (std::size_t i = 0; i < set.size(); ++i) {
    out << "  " << set[i].image_file.filename().string() << "  IoU " << scoreOrNull(run.counts[i].iou());
    if (!run.failures[i].empty()) out << "  (pipeline failed: " << run.failures[i] << "; scored as no road)";
    out << "\n";
  }
  const SegmentationScores& s = sum.scores;
  out << config.pipeline << " (bootstrap " << config.bootstrap << "): " << s.images << " images, " << sum.failed
      << " failed\n"
      << spaceText(config, bev) << "  IoU " << scoreOrNull(s.iou) << " (per image: median " << scoreOrNull(s.iou_median)
      << ", worst " << scoreOrNull(s.iou_worst) << ")\n"
      << "  precision " << scoreOrNull(s.precision) << ", recall " << scoreOrNull(s.recall) << "\n"
      << (run.confidence_given ? "  MaxF " + scoreOrNull(s.maxf) + ", AP " + scoreOrNull(s.ap) +
                                     " (from the per-pixel road confidence)\n"
                               : std::string("  MaxF null, AP null: no photo gave a per-pixel road confidence\n"))
      << "  baselines scored the same way: everything below the horizon IoU "
      << scoreOrNull(sum.baselines.horizon.iou) << ", the bootstrap region alone IoU "
      << scoreOrNull(sum.baselines.bootstrap.iou) << "\n"
      << "  margin over the better baseline " << (sum.margin && *sum.margin >= 0 ? "+" : "") << scoreOrNull(sum.margin)
      << "\n";
  if (!config.overlays.empty())
    out << "overlays in " << config.overlays << " (green TP, red FP, blue FN" << (bev ? "; STEM.bev.png in the grid" : "")
        << ")\n";
}

}  // namespace

int runEvalSegmentation(const EvalSegmentationConfig& config, std::ostream& out, std::ostream& err) {
  if (config.bev && config.camera.empty()) {
    err << "mapnav: error: eval segmentation: --bev needs --camera FILE (the camera that took the photos: the "
           "bird's-eye grid is laid on the ground it sees; an assumed camera would give made-up metres)\n";
    return kUsage;
  }
  return guarded(err, [&] {
    config.classes.validate();
    config.trapezoid.validate();
    if (config.bev) namingFlag("--bev-range / --bev-cell", [&] { config.bev_grid.validate(); });
    if (config.bootstrap != "trapezoid" && config.bootstrap != "labels-first-frame")
      throw InvalidInput("--bootstrap \"" + config.bootstrap + "\": expected trapezoid or labels-first-frame");
    loadPlugins(config.plugins, config.pipeline);
    auto pipeline = createPipeline(config.pipeline, config.options_json);
    const std::vector<Sample> set = readSet(config);
    const int w = set.front().image.width, h = set.front().image.height;
    const std::unique_ptr<Camera> camera = config.camera.empty() ? assumedPhotoCamera(w, h) : loadCamera(config.camera);
    if (camera->width() != w || camera->height() != h)
      throw InvalidInput(config.camera + ": the camera's image is " + std::to_string(camera->width()) + "x" +
                         std::to_string(camera->height()) + " but the photos are " + std::to_string(w) + "x" +
                         std::to_string(h));
    std::optional<BevSampling> bev;
    if (config.bev) {
      bev = bevSampling(*camera, config.bev_grid);
      if (bev->samples.empty())
        throw InvalidInput("--bev-range: no cell of the grid projects into the image of the camera " + config.camera);
    }
    const PixelSamples* samples = bev ? &bev->samples : nullptr;
    const Polygon2 bootstrap = config.bootstrap == "trapezoid"
                                   ? bottomTrapezoid(w, h, config.trapezoid)
                                   : largestRegionOutline(roadMask(set.front().label, config.classes));
    if (bootstrap.size() < 3) throw InvalidInput(set.front().label_file.string() + ": no road labelled to bootstrap from");
    const Run run = runPipeline(config, *pipeline, set, *camera, predictionFromImageRegion(bootstrap, *camera), samples);
    Summary sum;
    sum.scores = summarize(run.counts, run.confidence_given ? &run.histogram : nullptr);
    sum.baselines = scoreBaselines(set, *camera, bootstrap, config.classes, samples);
    sum.margin = marginOver(sum.scores.iou, sum.baselines);
    sum.failed = std::count_if(run.failures.begin(), run.failures.end(), [](const std::string& f) { return !f.empty(); });
    writeOverlays(config, set, run, bev);
    if (config.json) {
      printJson(config, set, run, sum, bev, out);
    } else {
      printText(config, set, run, sum, bev, out);
    }
    return static_cast<int>(kOk);
  });
}

// ---- the command line: `mapnav eval segmentation` -----------------------------------------------

void registerEvalCommands(CLI::App& app, Commands& commands) {
  auto* eval = commands.hold<EvalSegmentationConfig>();
  struct Texts {
    std::string road = "3", ignore, bev_range;
  };
  auto* text = commands.hold<Texts>();
  CLI::App* ev = app.add_subcommand("eval", "Score vision pipelines on labelled real photos (docs/eval.md)");
  ev->require_subcommand(1);
  CLI::App* es = ev->add_subcommand(
      "segmentation", "Run a pipeline over labelled photos: road IoU (set, per-image median and worst), precision, "
                      "recall, beside two baselines scored the same way (everything below the horizon is road; the "
                      "bootstrap region alone) and the margin over the better one");
  addPipelineOptions(es, eval->pipeline, eval->options_json, eval->plugins, "sidewalk");
  es->add_option("--images", eval->images, "Folder of RGB photos (PNG)")->required();
  es->add_option("--labels", eval->labels, "Folder of 1-channel class-index PNGs, one per photo, same file stem")->required();
  es->add_option("--road-values", text->road, "Label values that are road, comma-separated (CamVid: 3 road, 4 pavement)")
      ->default_val("3");
  es->add_option("--ignore-values", text->ignore, "Label values left out of the scores (CamVid: 11 unlabelled)");
  es->add_option("--bootstrap", eval->bootstrap,
                 "The road region the pipeline trains on: trapezoid (bottom centre, docs/eval.md) or labels-first-frame "
                 "(the first photo's largest labelled road region)")
      ->default_val("trapezoid");
  es->add_option("--camera", eval->camera,
                 "Camera file, its image the photos' size (default: an assumed level pin-hole of the photos' size, "
                 "docs/eval.md)")
      ->check(CLI::ExistingFile);
  CLI::Option* bev = es->add_flag(
      "--bev", eval->bev,
      "Score in a bird's-eye grid on the ground, as the KITTI road benchmark does (needs --camera): one sample per "
      "grid cell, the pixel its centre projects to; cells outside the image are left out");
  es->add_option("--bev-range", text->bev_range,
                 "The grid, metres: X0,X1 across (right of the camera positive), Z0,Z1 ahead of it (default KITTI's "
                 "-10,10,6,46)")
      ->needs(bev);
  es->add_option("--bev-cell", eval->bev_grid.cell_m, "The grid's cell side, metres (default KITTI's 0.05)")->needs(bev);
  es->add_option("--overlays", eval->overlays, "Folder to write overlays to: true positives green, false positives red, "
                                               "false negatives blue, ignored pixels dark");
  es->add_flag("--json", eval->json, "Print the scores as JSON");
  es->footer("Exit codes: 0 scored, 1 invalid input (an image without its label, a label of another size, a corrupt PNG), "
             "2 usage or I/O error (a missing folder).");
  es->callback(commands.choose([eval, text](std::ostream& out, std::ostream& err) {
    eval->classes.road = parseLabelValues("--road-values", text->road);
    eval->classes.ignore = parseLabelValues("--ignore-values", text->ignore);
    if (!text->bev_range.empty()) {
      const std::vector<double> r = parseNumbers("--bev-range", text->bev_range, 4, 4, "X0,X1,Z0,Z1 (metres)");
      eval->bev_grid.x_min_m = r[0], eval->bev_grid.x_max_m = r[1], eval->bev_grid.z_min_m = r[2],
      eval->bev_grid.z_max_m = r[3];
    }
    return runEvalSegmentation(*eval, out, err);
  }));
}

}  // namespace mapnav::cli
