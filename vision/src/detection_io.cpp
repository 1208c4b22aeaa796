#include "mapnav/vision/detection_io.h"

#include <cmath>

#include "mapnav/core/error.h"
#include "mapnav/core/json.h"

namespace mapnav {

void checkCameraFrame(const std::string& source, int width, int height, int channels, const Camera& camera) {
  if (channels != 3) throw InvalidInput(source + ": a camera frame must be an RGB image");
  if (width != camera.width() || height != camera.height()) {
    throw InvalidInput(source + ": the image is " + std::to_string(width) + "x" + std::to_string(height) +
                       " but the camera's is " + std::to_string(camera.width()) + "x" + std::to_string(camera.height()));
  }
}

namespace {

Json detectionPoints(const Polygon2& ring) {
  Json out = Json::array();
  for (const Vec2& p : ring) out.push_back(Json::array({std::round(p.x() * 1000) / 1000, std::round(p.y() * 1000) / 1000}));
  return out;
}

}  // namespace

std::string detectionToJson(const DetectedObject& d) {
  Json lines = Json::array();
  for (const DetectedLine& l : d.lines) {
    lines.push_back({{"label", l.label ? Json(*l.label) : Json(nullptr)},
                     {"score", std::round(l.score * 1000) / 1000},
                     {"frame_edge", l.frame_edge},
                     {"image", detectionPoints({l.image.a, l.image.b})},
                     {"vehicle", detectionPoints({l.vehicle.a, l.vehicle.b})}});
  }
  const std::optional<Segment2>& centre = d.centerline_vehicle;
  Json j = {{"status", d.status == DetectedObject::Status::Ok ? "ok" : "failed"},
            {"reason", d.reason},
            {"confidence", std::round(d.confidence * 1000) / 1000},
            {"region", {{"image", detectionPoints(d.region_image)}, {"vehicle", detectionPoints(d.region_vehicle)}}},
            {"lines", lines},
            {"centerline", centre ? detectionPoints({centre->a, centre->b}) : Json(nullptr)}};
  return dumpJson(j);
}

}  // namespace mapnav
