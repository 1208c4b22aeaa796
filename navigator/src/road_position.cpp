#include "mapnav/navigator/road_position.h"

#include <cmath>
#include <cstdio>
#include <regex>

#include "mapnav/core/error.h"

namespace mapnav {

RoadPosition parseRoadPosition(std::string_view text) {
  static const std::regex pattern(R"(^([A-Za-z][A-Za-z0-9_-]*)@([A-Za-z][A-Za-z0-9_-]*)\+([0-9]+(?:\.[0-9]*)?)(?:/([+-]?[0-9]+(?:\.[0-9]*)?))?$)");
  std::cmatch m;
  if (!std::regex_match(text.begin(), text.end(), m, pattern)) {
    throw InvalidInput("road position \"" + std::string(text) +
                       "\": expected ROAD@NODE+METERS[/LATERAL], e.g. R1@I1+3 or R1@I1+3/-0.4");
  }
  RoadPosition p;
  p.road = m[1];
  p.node = m[2];
  p.meters = std::stod(m[3]);
  if (m[4].matched) p.lateral = std::stod(m[4]);
  return p;
}

std::string toString(const RoadPosition& p) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "+%g", p.meters);
  std::string text = p.road + "@" + p.node + buffer;
  if (p.lateral != 0) {
    std::snprintf(buffer, sizeof buffer, "/%+g", p.lateral);
    text += buffer;
  }
  return text;
}

Pose2 toPose(const Map& map, const RoadPosition& p) {
  const Road& road = map.road(p.road);
  if (p.node != road.from && p.node != road.to) {
    throw InvalidInput("road position " + toString(p) + ": " + p.node + " is not an end of " + road.id + " (it runs " +
                       road.from + " to " + road.to + ")");
  }
  const double length = road.centerline.length();
  if (!(p.meters >= 0) || p.meters > length) {
    char buffer[160];
    std::snprintf(buffer, sizeof buffer, ": %g m is beyond the road's %.2f m", p.meters, length);
    throw InvalidInput("road position " + toString(p) + buffer);
  }
  const bool forward = p.node == road.from;
  const double s = forward ? p.meters : length - p.meters;
  const double heading = normalizeAngle(road.centerline.headingAt(s) + (forward ? 0.0 : kPi));
  const Vec2 at = road.centerline.pointAt(s) + p.lateral * leftNormal(unitVector(heading));
  return Pose2(at, heading);
}

}  // namespace mapnav
