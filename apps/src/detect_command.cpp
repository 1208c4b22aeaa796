#include "detect_command.h"

#include <cmath>
#include <sstream>
#include <ostream>

#include "cli.h"
#include "command_support.h"
#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/map/camera_io.h"
#include "mapnav/map/predict.h"
#include "mapnav/mission/image_region.h"
#include "mapnav/sim/image.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision_iface/pipeline.h"
#include "pipelines_command.h"

namespace mapnav::cli {

namespace {

struct Detection {
  Image image;
  Prediction prediction;
  DetectedObject detected;
};

Detection run(const Map* map, const DetectConfig& config) {
  loadPlugins(config.plugins);
  const auto camera = loadCamera(config.camera);
  Detection d;
  d.image = readPng(config.image);
  if (d.image.channels != 3) throw InvalidInput(config.image + ": a camera frame must be an RGB image");
  if (d.image.width != camera->width() || d.image.height != camera->height()) {
    throw InvalidInput(config.image + ": the image is " + std::to_string(d.image.width) + "x" + std::to_string(d.image.height) +
                       " but the camera's is " + std::to_string(camera->width()) + "x" + std::to_string(camera->height()));
  }
  d.prediction = map != nullptr ? predictView(*map, config.at ? toPose(*map, *config.at) : *config.pose, *camera)
                                : predictionFromImageRegion(config.train_region, *camera);
  const auto pipeline = createPipeline(config.pipeline, config.options_json);
  d.detected = pipeline->detect(VisionFrame{d.image.width, d.image.height, d.image.data.data(), camera.get(), 0.0},
                                d.prediction.view);
  return d;
}

Json points(const Polygon2& ring) {
  Json out = Json::array();
  for (const Vec2& p : ring) out.push_back(Json::array({std::round(p.x() * 1000) / 1000, std::round(p.y() * 1000) / 1000}));
  return out;
}

std::string toJson(const DetectedObject& d) {
  Json lines = Json::array();
  for (const DetectedLine& l : d.lines) {
    lines.push_back({{"label", l.label ? Json(*l.label) : Json(nullptr)},
                     {"score", std::round(l.score * 1000) / 1000},
                     {"frame_edge", l.frame_edge},
                     {"image", points({l.image.a, l.image.b})},
                     {"vehicle", points({l.vehicle.a, l.vehicle.b})}});
  }
  Json j = {{"status", d.status == DetectedObject::Status::Ok ? "ok" : "failed"},
            {"reason", d.reason},
            {"confidence", std::round(d.confidence * 1000) / 1000},
            {"region", {{"image", points(d.region_image)}, {"vehicle", points(d.region_vehicle)}}},
            {"lines", lines},
            {"centerline", d.centerline_vehicle ? points({d.centerline_vehicle->a, d.centerline_vehicle->b}) : Json(nullptr)}};
  return dumpJson(j);
}

}  // namespace

int runDetect(const DetectConfig& config, std::ostream& out, std::ostream& err) {
  return withMap(config.map, err, [&](const Map& map) {
    const Detection d = run(&map, config);
    if (!config.output.empty()) writePng(drawDetection(d.image, d.prediction.view, d.detected), config.output);
    if (config.json) {
      out << toJson(d.detected);
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

}  // namespace mapnav::cli
