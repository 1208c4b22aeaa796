#pragma once
// A route for people and for QGIS: drawn on the map, or as GeoJSON.
#include <string>

#include "mapnav/map/map_render.h"
#include "mapnav/navigator/route.h"
#include "mapnav/render/canvas.h"

namespace mapnav {

/// The map with the route drawn on it: a bold line from the start (green) to the goal (red), and
/// the turns numbered.
render::Canvas renderRoute(const Map& map, const Route& route, const MapRenderOptions& options = {});

/// A FeatureCollection in lon/lat: the route as a LineString (properties: from, to, length_m,
/// dialogue) and the start and goal as Points. Throws InvalidInput when the map has no origin.
std::string routeToGeoJson(const Map& map, const Route& route);

}  // namespace mapnav
