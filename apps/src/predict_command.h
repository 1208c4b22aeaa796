#pragma once
#include <iosfwd>
#include <optional>
#include <string>

#include "mapnav/geometry/pose2.h"
#include "mapnav/map/predict.h"
#include "mapnav/navigator/road_position.h"

namespace mapnav::cli {

struct PredictConfig {
  std::string map;
  std::string camera;
  std::optional<Pose2> pose;        ///< in the world frame; or
  std::optional<RoadPosition> at;   ///< on a road
  bool json = false;                ///< print the prediction as JSON
  std::string output;               ///< picture to write (.png / .svg), "" for none
  PredictOptions options;           ///< --near, --far (the footprint); the rest at their defaults
};

/// "X,Y,HEADING_DEG" (metres, metres, degrees). Throws InvalidInput saying what is wrong.
Pose2 parsePose(const std::string& text);

/// `mapnav predict`: what the camera should see from a pose.
int runPredict(const PredictConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
