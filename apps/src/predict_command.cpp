#include "predict_command.h"

#include <cmath>
#include <ostream>
#include <sstream>

#include "cli.h"
#include "command_support.h"
#include "mapnav/core/error.h"
#include "mapnav/map/camera_io.h"
#include "mapnav/map/predict.h"
#include "mapnav/map/predict_render.h"
#include "mapnav/navigator/road_position.h"

namespace mapnav::cli {

Pose2 parsePose(const std::string& text) {
  const std::vector<double> v = parseNumbers("--pose", text, 3, 3, "X,Y,HEADING_DEG (metres, metres, degrees)");
  return Pose2(v[0], v[1], degToRad(v[2]));
}

namespace {

// The dialogue's sentence: "Vision will see straight road and cross intersection. The color on the left is ..."
void describe(const Prediction& p, std::ostream& out) {
  if (p.view.footprint.empty()) {
    out << "The camera sees no ground from here (it looks above the horizon).\n";
    return;
  }
  if (p.empty()) {
    out << "Vision will see no road from here.\n";
    return;
  }
  out << "Vision will see";
  for (std::size_t i = 0; i < p.view.regions.size(); ++i) {
    const PredictedRegion& r = p.view.regions[i];
    out << (i == 0 ? " " : i + 1 == p.view.regions.size() ? " and " : ", ") << r.kind << " " << r.id;
  }
  out << ".\n";
  for (const InterestSegment& s : p.view.segments) {
    char line[256];
    std::snprintf(line, sizeof line, "  %-14s %5.1f m  from (%5.1f, %5.1f) to (%5.1f, %5.1f) m  left %s, right %s\n",
                  s.id.c_str(), s.vehicle.length(), s.vehicle.a.x(), s.vehicle.a.y(), s.vehicle.b.x(), s.vehicle.b.y(),
                  s.left_surface.c_str(), s.right_surface.c_str());
    out << line;
  }
  for (const SegmentRelation& rel : p.view.relations) {
    char line[160];
    if (rel.type == SegmentRelation::Type::Parallel) {
      std::snprintf(line, sizeof line, "  %s ∥ %s, %.2f m apart\n", rel.a.c_str(), rel.b.c_str(), rel.separation_m);
    } else {
      std::snprintf(line, sizeof line, "  %s × %s at %.0f°\n", rel.a.c_str(), rel.b.c_str(), radToDeg(rel.angle_rad));
    }
    out << line;
  }
}

}  // namespace

int runPredict(const PredictConfig& config, std::ostream& out, std::ostream& err) {
  return withMap(config.map, err, [&](const Map& map) {
    const auto camera = loadCamera(config.camera);
    const Pose2 pose = config.at ? toPose(map, *config.at) : *config.pose;
    PredictOptions options;
    options.near_m = config.near_m;
    options.far_m = config.far_m;
    const Prediction prediction = predictView(map, pose, *camera, options);
    if (!config.output.empty()) renderPrediction(map, prediction, *camera).save(config.output);
    if (config.json) {
      out << predictionToJson(prediction);
    } else {
      describe(prediction, out);
      if (!config.output.empty()) out << "wrote " << config.output << "\n";
    }
    return static_cast<int>(kOk);
  });
}

}  // namespace mapnav::cli
