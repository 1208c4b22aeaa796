#pragma once
// Shared by the two halves of the GeoJSON import (internal to map/): a feature as read, before
// projection, which geojson_parse.cpp reads and the map builder in geojson.cpp turns into the map;
// the members of a feature's properties that mapnav interprets, which the reader leaves out of the
// kept properties and exportGeoJson writes; and the reading of a whole FeatureCollection.
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "mapnav/core/issue.h"
#include "mapnav/map/geodesy.h"
#include "mapnav/map/map.h"

namespace mapnav::geojson {

// A feature as read, before projection: its lon/lat geometry and its properties.
struct RawFeature {
  std::string pointer;  // "/features/k"
  enum class Kind { Road, Point, Polygon, Landmark } kind = Kind::Road;  // Point, Polygon: intersections
  std::vector<LatLon> coordinates;  // the point, or the outer ring without its closing point
  std::vector<std::vector<LatLon>> lines;  // a road's centre line: one (LineString) or more (MultiLineString)
  bool id_from_name = false;  // the id is the feature's "id" member or its "name" property, not properties.id
  std::optional<std::string> id, kind_name, from, to, surface, left, right;
  std::optional<double> width, cost_factor, position_sigma_m;
  std::optional<bool> oneway;
  std::optional<int> layer;
  std::optional<RoadStructure> structure;
  std::optional<LatLon> center;
  std::optional<LandmarkKind> landmark;     // a landmark's kind (properties.landmark)
  std::optional<double> radius, height;     // a landmark's size
  std::optional<std::string> road;          // the road a landmark stands beside
  Properties extra;  // the members mapnav does not interpret for this kind of feature, kept as they are
};

// The members of a feature's properties that mapnav interprets: for roads, intersections and landmarks.
// A kept property named like one of them (an OSM way's `surface` tag) is written inside the member
// kShadowed instead, and read back from there.
inline const std::set<std::string, std::less<>> kRoadMembers{"id",    "from",   "to",          "width", "surface",   "left",
                                                             "right", "oneway", "cost_factor", "layer", "structure", "position_sigma_m",
                                                             "mapnav_kept"};
inline const std::set<std::string, std::less<>> kIntersectionMembers{"id", "kind", "center", "mapnav_kept"};
inline const std::set<std::string, std::less<>> kLandmarkMembers{"landmark", "id", "radius", "height", "road", "mapnav_kept"};
inline constexpr const char* kShadowed = "mapnav_kept";

// The FeatureCollection's features as read, and what its "mapnav" member says (the map's name and
// surfaces into `map`, the local frame's origin into `file_origin`, its position_sigma_m into
// `file_sigma`). Nothing when the document is
// not a FeatureCollection with a "features" array; bad features are left out with their issues.
std::optional<std::vector<RawFeature>> readFeatureCollection(std::string_view text, Issues& issues, MapData& map,
                                                             std::optional<GeoOrigin>& file_origin,
                                                             std::optional<double>& file_sigma);

}  // namespace mapnav::geojson
