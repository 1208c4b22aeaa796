#include "detect_command.h"

#include <cmath>
#include <sstream>
#include <ostream>

#include "cli.h"
#include "command_line.h"
#include "command_support.h"
#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/image/png.h"
#include "mapnav/map/predict.h"
#include "mapnav/mission/image_region.h"
#include "mapnav/tokens/token_json.h"
#include "mapnav/vision/detection_io.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision_iface/pipeline.h"
#include "pipelines_command.h"
#include "predict_command.h"

namespace mapnav::cli {

namespace {

struct Detection {
  Image image;
  Prediction prediction;
  DetectedObject detected;
};

Detection run(const Map* map, const DetectConfig& config) {
  loadPlugins(config.plugins, config.pipeline);
  const auto camera = loadCamera(config.camera);
  Detection d;
  d.image = readPng(config.image);
  checkCameraFrame(config.image, d.image.width, d.image.height, d.image.channels, *camera);
  d.prediction = map != nullptr ? predictView(*map, config.at ? toPose(*map, *config.at) : *config.pose, *camera)
                                : predictionFromImageRegion(config.train_region, *camera);
  const auto pipeline = createPipeline(config.pipeline, config.options_json);
  d.detected = pipeline->detect(VisionFrame{d.image.width, d.image.height, d.image.data.data(), camera.get(), 0.0},
                                d.prediction.view);
  return d;
}

}  // namespace

int runDetect(const DetectConfig& config, std::ostream& out, std::ostream& err) {
  return withMap(config.map, err, [&](const Map& map) {
    const Detection d = run(&map, config);
    if (!config.output.empty()) writePng(drawDetection(d.image, d.prediction.view, d.detected), config.output);
    if (config.json) {
      out << dumpJson(toJson(d.detected));
    } else {
      std::size_t labelled = 0;
      for (const DetectedLine& l : d.detected.lines) labelled += l.label ? 1 : 0;
      out << (d.detected.status == DetectedObject::Status::Ok ? "ok" : "failed: " + d.detected.reason) << ": "
          << d.detected.lines.size() << " lines, " << labelled << " matched to the prediction\n";
      for (const DetectedLine& l : d.detected.lines) {
        if (l.label) out << "  " << *l.label << " (score " << l.score << ")\n";
      }
    }
    return static_cast<int>(d.detected.status == DetectedObject::Status::Ok ? kOk : kInvalid);
  });
}

std::vector<Vec2> parsePixelPolygon(const std::string& text) {
  std::vector<Vec2> polygon;
  std::stringstream in(text);
  for (std::string point; std::getline(in, point, ';');) {
    const auto uv = parseNumbers("--train-region", point, 2, 2, "U,V;U,V;U,V (pixels)");
    polygon.emplace_back(uv[0], uv[1]);
  }
  if (polygon.size() < 3) throw InvalidInput("--train-region \"" + text + "\": a polygon needs at least 3 points U,V;U,V;U,V");
  return polygon;
}

int runSegment(const DetectConfig& config, std::ostream& out, std::ostream& err) {
  auto body = [&](const Map* map) {
    const Detection d = run(map, config);
    if (d.detected.status != DetectedObject::Status::Ok) {
      err << "mapnav: error: " << config.image << ": " << d.detected.reason << "; nothing written\n";
      return static_cast<int>(kInvalid);
    }
    writePng(regionMask(d.detected, d.image.width, d.image.height), config.output);
    if (!config.overlay.empty()) writePng(drawDetection(d.image, d.prediction.view, d.detected), config.overlay);
    out << "wrote " << config.output << "\n";
    return static_cast<int>(kOk);
  };
  if (!config.train_region.empty()) return guarded(err, [&] { return body(nullptr); });
  return withMap(config.map, err, [&](const Map& map) { return body(&map); });
}

// ---- the command line: `mapnav detect` and `mapnav segment` -------------------------------------

namespace {

/// What the command line gives before it is parsed into the config: the pose as text.
struct DetectLine {
  DetectConfig config;
  std::string pose, at, train_region;
};

/// The options detect and segment share.
void addVisionOptions(CLI::App* c, DetectLine& line) {
  addPipelineOptions(c, line.config.pipeline, line.config.options_json, line.config.plugins, "sidewalk");
  c->add_option("image", line.config.image, "Camera frame (RGB PNG)")->required()->check(CLI::ExistingFile);
  c->add_option("--map", line.config.map, "Map file, for the prediction")->check(CLI::ExistingFile);
  c->add_option("--camera", line.config.camera, "Camera file")->required()->check(CLI::ExistingFile);
  auto* pose = c->add_option("--pose", line.pose, "Vehicle pose X,Y,HEADING_DEG, for the prediction");
  auto* at = c->add_option("--at", line.at, "Vehicle on a road: ROAD@NODE+METERS");
  pose->excludes(at);
  at->excludes(pose);
}

using VisionRun = int (*)(const DetectConfig&, std::ostream&, std::ostream&);

/// The body of detect or segment: the prediction from --map and the pose, or segment's training region.
Commands::Body visionCommand(DetectLine* line, VisionRun run) {
  return [line, run](std::ostream& out, std::ostream& err) {
    DetectConfig& detect = line->config;
    if (!line->train_region.empty()) {
      detect.train_region = parsePixelPolygon(line->train_region);
      return run(detect, out, err);
    }
    if (detect.map.empty() || (line->pose.empty() && line->at.empty())) {
      throw UsageError("the prediction needs --map and --pose (or --at); segment also takes --train-region instead");
    }
    if (!line->pose.empty()) detect.pose = parsePose(line->pose);
    if (!line->at.empty()) detect.at = parseRoadPosition(line->at);
    return run(detect, out, err);
  };
}

}  // namespace

void registerDetectCommands(CLI::App& app, Commands& commands) {
  // detect and segment share their options: one holds them whichever is given.
  auto* line = commands.hold<DetectLine>();
  CLI::App* dt = app.add_subcommand("detect", "Run a vision pipeline on a frame against the prediction: the Detected Object");
  addVisionOptions(dt, *line);
  dt->add_flag("--json", line->config.json, "Print the DetectedObject as JSON");
  dt->add_option("-o,--output", line->config.output, "Overlay picture (PNG): predicted segments thin, detected lines bold")
      ->check(outputFile(false));
  dt->footer("Exit codes: 0 detected, 1 the pipeline failed on the frame (the reason is printed) or bad input, 2 usage/I-O.");
  dt->callback(commands.choose(visionCommand(line, runDetect)));
  CLI::App* sg = app.add_subcommand("segment", "Run a vision pipeline on a frame and write the road mask it finds");
  addVisionOptions(sg, *line);
  sg->add_option("-o,--output", line->config.output, "Road mask to write (PNG, 255 = road)")->required();
  sg->add_option("--overlay", line->config.overlay, "Also the overlay picture (PNG)");
  sg->add_option("--train-region", line->train_region, "Train on this image polygon U,V;U,V;U,V (pixels) instead of a map prediction");
  sg->callback(commands.choose(visionCommand(line, runSegment)));
}

}  // namespace mapnav::cli
