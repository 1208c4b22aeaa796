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
#include "mapnav/core/error.h"
#include "mapnav/core/interrupt.h"
#include "mapnav/core/json.h"
#include "mapnav/image/png.h"
#include "mapnav/map/camera_io.h"
#include "mapnav/mission/image_region.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision_iface/pipeline.h"
#include "pipelines_command.h"

namespace mapnav::cli {

namespace fs = std::filesystem;

namespace {

struct Sample {
  fs::path image_file, label_file;
  Image image, label;
};

// Every image with its label, read and checked before anything runs or is written.
std::vector<Sample> readSet(const EvalSegmentationConfig& config) {
  for (const auto& [option, dir] : {std::pair{"--images", config.images}, std::pair{"--labels", config.labels}}) {
    std::error_code ec;
    if (!fs::is_directory(dir, ec)) throw IoError(std::string(option) + " " + dir + ": no such folder");
  }
  std::vector<fs::path> files;
  std::error_code ec;
  for (fs::directory_iterator it(config.images, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code type_ec;
    if (it->is_regular_file(type_ec) && it->path().extension() == ".png") files.push_back(it->path());
  }
  if (ec) throw IoError(config.images + ": cannot list the folder: " + ec.message());
  std::sort(files.begin(), files.end());
  if (files.empty()) throw InvalidInput(config.images + ": no .png images in the folder");
  std::vector<Sample> set;
  for (const fs::path& f : files) {
    Sample s;
    s.image_file = f;
    s.label_file = fs::path(config.labels) / (f.stem().string() + ".png");
    if (std::error_code label_ec; !fs::is_regular_file(s.label_file, label_ec))
      throw InvalidInput(f.string() + ": no label " + s.label_file.string() + " (labels are matched by file stem)");
    s.image = readPng(f);
    s.label = readPng(s.label_file);
    if (s.image.channels != 3) throw InvalidInput(f.string() + ": expected an RGB photo");
    if (s.label.channels != 1) throw InvalidInput(s.label_file.string() + ": expected a 1-channel PNG of class indices");
    if (s.label.width != s.image.width || s.label.height != s.image.height)
      throw InvalidInput(s.label_file.string() + ": the label is " + std::to_string(s.label.width) + "x" +
                         std::to_string(s.label.height) + " but its image is " + std::to_string(s.image.width) + "x" +
                         std::to_string(s.image.height));
    if (!set.empty() && (s.image.width != set.front().image.width || s.image.height != set.front().image.height))
      throw InvalidInput(f.string() + ": every image must have the size of the first (" +
                         std::to_string(set.front().image.width) + "x" + std::to_string(set.front().image.height) + ")");
    set.push_back(std::move(s));
  }
  return set;
}

/// A score in the JSON and in the text: 4 decimals, null when undefined.
Json number(const std::optional<double>& v) { return roundedOrNull(v, 4); }
std::string scoreOrNull(const std::optional<double>& v) { return fixedOr(v, 4, "null"); }

// The two trivial answers the pipeline must beat, scored like it over the same photos.
struct Baselines {
  SegmentationScores horizon;    ///< every pixel below the horizon is road
  SegmentationScores bootstrap;  ///< the bootstrap region alone is road
};

Baselines scoreBaselines(const std::vector<Sample>& set, const Camera& camera, const Polygon2& bootstrap,
                         const LabelClasses& classes) {
  const Image horizon = groundMask(camera);
  const Image region = regionMask(bootstrap, camera.width(), camera.height());
  std::vector<PixelCounts> horizon_counts, region_counts;
  for (const Sample& s : set) {
    horizon_counts.push_back(countPixels(horizon, s.label, classes));
    region_counts.push_back(countPixels(region, s.label, classes));
  }
  return {summarize(horizon_counts), summarize(region_counts)};
}

// The pipeline's IoU less the better baseline's; nothing when either is undefined.
std::optional<double> marginOver(const std::optional<double>& iou, const Baselines& baselines) {
  if (!iou || !baselines.horizon.iou || !baselines.bootstrap.iou) return std::nullopt;
  return *iou - std::max(*baselines.horizon.iou, *baselines.bootstrap.iou);
}

}  // namespace

std::unique_ptr<Camera> assumedPhotoCamera(int width, int height) {
  CameraIntrinsics in;
  in.width = width;
  in.height = height;
  in.fx = in.fy = 0.9 * width;
  in.cx = (width - 1) / 2.0;
  in.cy = (height - 1) / 2.0;
  CameraMount mount;
  mount.height_m = 1.3;
  mount.tilt_rad = 0.0;
  return createCamera(LensModel::Pinhole, in, mount);
}

int runEvalSegmentation(const EvalSegmentationConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    config.classes.validate();
    config.trapezoid.validate();
    if (config.bootstrap != "trapezoid" && config.bootstrap != "labels-first-frame")
      throw InvalidInput("--bootstrap \"" + config.bootstrap + "\": expected trapezoid or labels-first-frame");
    loadPlugins(config.plugins);
    auto pipeline = createPipeline(config.pipeline, config.options_json);
    const std::vector<Sample> set = readSet(config);
    const int w = set.front().image.width, h = set.front().image.height;
    const std::unique_ptr<Camera> camera = config.camera.empty() ? assumedPhotoCamera(w, h) : loadCamera(config.camera);
    if (camera->width() != w || camera->height() != h)
      throw InvalidInput(config.camera + ": the camera's image is " + std::to_string(camera->width()) + "x" +
                         std::to_string(camera->height()) + " but the photos are " + std::to_string(w) + "x" +
                         std::to_string(h));
    const Polygon2 bootstrap = config.bootstrap == "trapezoid"
                                   ? bottomTrapezoid(w, h, config.trapezoid)
                                   : largestRegionOutline(roadMask(set.front().label, config.classes));
    if (bootstrap.size() < 3) throw InvalidInput(set.front().label_file.string() + ": no road labelled to bootstrap from");
    const Prediction prediction = predictionFromImageRegion(bootstrap, *camera);

    std::vector<PixelCounts> counts;
    std::vector<std::string> failures;  // per image, empty when the pipeline found a region
    std::vector<Image> overlays;
    // MaxF and AP from the pipelines' per-pixel confidence; a failed frame's is 0 everywhere. A
    // pipeline that gives none leaves them null rather than made up from the binary region.
    ScoreHistogram histogram;
    bool confidence_given = false;
    const Image no_confidence(w, h, 1);
    for (const Sample& s : set) {
      throwIfInterrupted();  // Ctrl-C: stop before the overlays are written
      VisionFrame frame{w, h, s.image.data.data(), camera.get(), 0.0};
      frame.want_masks = true;
      const DetectedObject d = pipeline->detect(frame, prediction.view);
      const bool ok = d.status == DetectedObject::Status::Ok;
      const Image mask = ok ? regionMask(d, w, h) : Image(w, h, 1);
      counts.push_back(countPixels(mask, s.label, config.classes));
      failures.push_back(ok ? "" : d.reason);
      confidence_given = confidence_given || !d.road_confidence.empty();
      histogram.add(d.road_confidence.empty() ? no_confidence : d.road_confidence, s.label, config.classes);
      if (!config.overlays.empty()) overlays.push_back(drawSegmentationOverlay(s.image, mask, s.label, config.classes));
    }
    const SegmentationScores scores = summarize(counts, confidence_given ? &histogram : nullptr);
    const Baselines baselines = scoreBaselines(set, *camera, bootstrap, config.classes);
    const std::optional<double> margin = marginOver(scores.iou, baselines);
    if (!config.overlays.empty()) {
      fs::create_directories(config.overlays);
      for (std::size_t i = 0; i < set.size(); ++i)
        writePng(overlays[i], fs::path(config.overlays) / (set[i].image_file.stem().string() + ".png"));
    }
    const auto failed = std::count_if(failures.begin(), failures.end(), [](const std::string& f) { return !f.empty(); });
    if (config.json) {
      Json per_image = Json::array();
      for (std::size_t i = 0; i < set.size(); ++i)
        per_image.push_back({{"image", set[i].image_file.filename().string()},
                             {"iou", number(counts[i].iou())},
                             {"failed", failures[i].empty() ? Json(nullptr) : Json(failures[i])}});
      const Json j = {{"pipeline", config.pipeline}, {"bootstrap", config.bootstrap},
                      {"images", scores.images},     {"failed", failed},
                      {"iou", number(scores.iou)},   {"iou_median", number(scores.iou_median)},
                      {"iou_worst", number(scores.iou_worst)}, {"precision", number(scores.precision)},
                      {"recall", number(scores.recall)},       {"maxf", number(scores.maxf)},
                      {"ap", number(scores.ap)},
                      {"baseline_horizon_iou", number(baselines.horizon.iou)},
                      {"baseline_bootstrap_iou", number(baselines.bootstrap.iou)},
                      {"margin", number(margin)},              {"per_image", per_image}};
      out << dumpJson(j);
    } else {
      for (std::size_t i = 0; i < set.size(); ++i) {
        out << "  " << set[i].image_file.filename().string() << "  IoU " << scoreOrNull(counts[i].iou());
        if (!failures[i].empty()) out << "  (pipeline failed: " << failures[i] << "; scored as no road)";
        out << "\n";
      }
      out << config.pipeline << " (bootstrap " << config.bootstrap << "): " << scores.images << " images, " << failed
          << " failed\n"
          << "  IoU " << scoreOrNull(scores.iou) << " (per image: median " << scoreOrNull(scores.iou_median) << ", worst "
          << scoreOrNull(scores.iou_worst) << ")\n"
          << "  precision " << scoreOrNull(scores.precision) << ", recall " << scoreOrNull(scores.recall) << "\n"
          << (confidence_given ? "  MaxF " + scoreOrNull(scores.maxf) + ", AP " + scoreOrNull(scores.ap) +
                                     " (from the per-pixel road confidence)\n"
                               : std::string("  MaxF null, AP null: no photo gave a per-pixel road confidence\n"))
          << "  baselines scored the same way: everything below the horizon IoU " << scoreOrNull(baselines.horizon.iou)
          << ", the bootstrap region alone IoU " << scoreOrNull(baselines.bootstrap.iou) << "\n"
          << "  margin over the better baseline " << (margin && *margin >= 0 ? "+" : "") << scoreOrNull(margin) << "\n";
      if (!config.overlays.empty()) out << "overlays in " << config.overlays << " (green TP, red FP, blue FN)\n";
    }
    return static_cast<int>(kOk);
  });
}

// ---- the command line: `mapnav eval segmentation` -----------------------------------------------

namespace {

/// "3,4": label values, whole numbers in [0, 255]. Throws InvalidInput naming the option.
std::vector<int> parseLabelValues(const std::string& option, const std::string& text) {
  std::vector<int> out;
  if (text.empty()) return out;
  for (double v : parseNumbers(option, text, 1, 256, "label values V[,V...] (0-255)")) {
    if (v != std::floor(v)) throw InvalidInput(option + " \"" + text + "\": label values are whole numbers");
    out.push_back(static_cast<int>(v));
  }
  return out;
}

}  // namespace

void registerEvalCommands(CLI::App& app, Commands& commands) {
  auto* eval = commands.hold<EvalSegmentationConfig>();
  struct Texts {
    std::string road = "3", ignore;
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
  es->add_option("--camera", eval->camera, "Camera file (default: an assumed level pin-hole of the photos' size, docs/eval.md)")
      ->check(CLI::ExistingFile);
  es->add_option("--overlays", eval->overlays, "Folder to write overlays to: true positives green, false positives red, "
                                               "false negatives blue, ignored pixels dark");
  es->add_flag("--json", eval->json, "Print the scores as JSON");
  es->footer("Exit codes: 0 scored, 1 invalid input (an image without its label, a label of another size, a corrupt PNG), "
             "2 usage or I/O error (a missing folder).");
  es->callback(commands.choose([eval, text](std::ostream& out, std::ostream& err) {
    eval->classes.road = parseLabelValues("--road-values", text->road);
    eval->classes.ignore = parseLabelValues("--ignore-values", text->ignore);
    return runEvalSegmentation(*eval, out, err);
  }));
}

}  // namespace mapnav::cli
