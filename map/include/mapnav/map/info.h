#pragma once
#include <map>
#include <string>

#include "mapnav/map/map.h"

namespace mapnav {

/// What `mapnav map info` tells about a map.
struct MapInfo {
  std::string name;
  std::size_t intersections = 0;
  std::size_t roads = 0;
  std::map<std::string, std::size_t> intersections_by_kind;  ///< kind name → count
  std::map<std::string, std::size_t> roads_by_surface;       ///< surface → count
  std::size_t landmarks = 0;
  std::map<std::string, std::size_t> landmarks_by_kind;      ///< kind name ("tree") → count
  double total_length_m = 0;                                 ///< sum of centre-line lengths
  double paved_area_m2 = 0;                                  ///< sum of length × width
  Box2 bounds;                                               ///< paved area
  std::size_t components = 0;
  std::optional<GeoOrigin> origin;
};

MapInfo describeMap(const Map& map);
/// For people: a few aligned lines.
std::string toText(const MapInfo& info);
/// For programs: one JSON object.
std::string toJson(const MapInfo& info);

}  // namespace mapnav
