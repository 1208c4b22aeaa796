#pragma once
#include <iosfwd>
#include <string>
#include <vector>

#include "mapnav/navigator/road_position.h"

namespace mapnav::cli {

struct RouteConfig {
  std::string map;
  RoadPosition from, to;
  std::vector<std::string> blocked;  ///< road and intersection ids
  bool json = false;                 ///< print the route as JSON instead of the dialogue
  std::string output;                ///< .png / .svg picture or .geojson, "" for none
};

/// `mapnav route`: the cheapest route between two road positions, as motion commands.
int runRoute(const RouteConfig& config, std::ostream& out, std::ostream& err);

}  // namespace mapnav::cli
