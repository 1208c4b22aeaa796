#pragma once
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "mapnav/geometry/pose2.h"
#include "mapnav/navigator/road_position.h"

namespace mapnav::cli {

struct DetectConfig {
  std::string pipeline = "sidewalk";
  std::string options_json = "{}";
  std::vector<std::string> plugins;
  std::string image;
  std::string map, camera;
  std::optional<Pose2> pose;
  std::optional<RoadPosition> at;
  std::vector<Vec2> train_region;  ///< segment: train on this image polygon instead of a map prediction
  bool json = false;
  std::string output;   ///< detect: overlay picture; segment: the road mask
  std::string overlay;  ///< segment: also the overlay
};

/// `mapnav detect`: the DetectedObject for one image and the prediction at a pose.
int runDetect(const DetectConfig& config, std::ostream& out, std::ostream& err);
/// "U,V;U,V;U,V" (pixels) → a polygon. Throws InvalidInput.
std::vector<Vec2> parsePixelPolygon(const std::string& text);

/// `mapnav segment`: the road mask a pipeline finds in one image, trained from the map's prediction
/// or from a region of the image the user gives.
int runSegment(const DetectConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
