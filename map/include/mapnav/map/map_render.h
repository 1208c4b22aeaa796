#pragma once
// Pictures of a map: roads as filled polygons in their surface colours, intersections, ids,
// scale bar and north arrow. Later issues draw routes, views and trajectories on top.
#include "mapnav/map/map.h"
#include "mapnav/render/canvas.h"

namespace mapnav {

struct MapRenderOptions {
  int width_px = 1600;        ///< picture width; the height follows from the map's aspect
  double margin_px = 48.0;    ///< free border around the map
  bool labels = true;         ///< draw road and intersection ids
  bool title = true;          ///< draw the map's name at the top

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

struct MapPicture {
  render::Canvas canvas;
  render::View view;  ///< world → pixel, for drawing more on top
};

MapPicture renderMap(const Map& map, const MapRenderOptions& options = {});

}  // namespace mapnav
