#pragma once
// Pictures of a map: roads as filled polygons in their surface colours, intersections, ids,
// scale bar and north arrow. Later issues draw routes, views and trajectories on top.
#include <vector>

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

/// The map's layers (shoulders, paved areas, centre lines, ids) for these roads and intersections,
/// drawn through `view`: the building block of every picture with a map in it.
void drawMapLayers(render::Canvas& canvas, const render::View& view, const Map& map,
                   const std::vector<const Road*>& roads, const std::vector<const Intersection*>& intersections,
                   bool labels);

/// The picture's ground: the shoulder most roads have, lightened so roads and labels stand out.
render::Rgb groundColor(const Map& map);

}  // namespace mapnav
