#include "predict_command.h"

#include <cmath>
#include <ostream>
#include <sstream>

#include "cli.h"
#include "command_line.h"
#include "command_support.h"
#include "mapnav/core/error.h"
#include "mapnav/geometry/camera_io.h"
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
  for (const PredictedLandmark& l : p.view.landmarks) {
    char line[200];
    std::snprintf(line, sizeof line, "  landmark %-8s %-7s at (%5.1f, %5.1f) m, base pixel (%.0f, %.0f), %.0f px tall\n",
                  l.id.c_str(), l.kind.c_str(), l.vehicle.x(), l.vehicle.y(), l.image_base.x(), l.image_base.y(),
                  (l.image_top - l.image_base).norm());
    out << line;
  }
}

}  // namespace

int runPredict(const PredictConfig& config, std::ostream& out, std::ostream& err) {
  return withMap(config.map, err, [&](const Map& map) {
    const auto camera = loadCamera(config.camera);
    const Pose2 pose = config.at ? toPose(map, *config.at) : *config.pose;
    const Prediction prediction = predictView(map, pose, *camera, config.options);
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

void registerPredictCommand(CLI::App& app, Commands& commands) {
  auto* predict = commands.hold<PredictConfig>();
  struct Texts {
    std::string pose, at;
  };
  auto* text = commands.hold<Texts>();
  CLI::App* p = app.add_subcommand("predict", "What the camera should see from a pose: objects, interest segments, relations");
  p->add_option("--map", predict->map, "Map file")->required()->check(CLI::ExistingFile);
  p->add_option("--camera", predict->camera, "Camera file (mapnav-camera/1, docs/camera-format.md)")
      ->required()
      ->check(CLI::ExistingFile);
  auto* pose = p->add_option("--pose", text->pose, "Vehicle pose X,Y,HEADING_DEG in the map's frame (metres, degrees CCW from east)");
  auto* at = p->add_option("--at", text->at, "Vehicle on a road: ROAD@NODE+METERS[/LATERAL], e.g. R1@I1+3 (facing away from NODE)");
  pose->excludes(at);
  at->excludes(pose);
  p->add_flag("--json", predict->json, "Print the prediction as JSON instead of sentences");
  p->add_option("-o,--output", predict->output, "Also draw the map with the footprint beside the predicted image: OUT.png or OUT.svg")
      ->check(outputFile(false));
  p->add_option("--near", predict->options.near_m, "Nearest ground distance ahead of the camera to predict, m")
      ->capture_default_str()
      ->check(commands.ruleCheck(predictOptionTable(), "near_m"));
  p->add_option("--far", predict->options.far_m, "Farthest ground distance from the camera to predict, m (> --near)")
      ->capture_default_str()
      ->check(commands.ruleCheck(predictOptionTable(), "far_m"));
  p->footer("Exactly one of --pose and --at. Exit codes: 0 success (an empty view too), 1 invalid map, camera or\n"
            "position, 2 usage or I/O error.");
  p->callback(commands.choose([predict, text](std::ostream& out, std::ostream& err) {
    if (text->pose.empty() && text->at.empty()) {
      throw UsageError("predict needs the vehicle's pose: --pose X,Y,HEADING_DEG or --at ROAD@NODE+METERS");
    }
    if (!text->pose.empty()) predict->pose = parsePose(text->pose);
    if (!text->at.empty()) predict->at = parseRoadPosition(text->at);
    return runPredict(*predict, out, err);
  }));
}

}  // namespace mapnav::cli
