#pragma once
// Pictures of a map: roads as filled polygons in their surface colours, intersections, landmarks,
// ids, scale bar and north arrow. Later issues draw routes, views and trajectories on top.
#include <vector>

#include "mapnav/core/option_table.h"
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

/// MapRenderOptions' fields by name, with their rules.
const OptionTable<MapRenderOptions>& mapRenderOptionTable();

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

/// Landmarks as symbols, each a few pixels across at least whatever the scale: a tree a green disc
/// (kTreeCrown; radius a third of its height, 1–4 m) with a dark trunk dot (kTreeTrunk, its radius),
/// a pole a small dark dot (kPole), a bollard a small grey square (kBollard), a bench a short brown
/// bar along the road beside it (kBench, its length 2 × radius), a manhole cover a grey circle
/// (kManhole, its radius). Flat covers are drawn first, upright landmarks over them.
inline constexpr render::Rgb kTreeCrown{56, 142, 60}, kTreeTrunk{78, 52, 30}, kPole{45, 45, 50},
    kBollard{150, 150, 150}, kBench{150, 95, 45}, kManhole{120, 120, 120};
void drawLandmarks(render::Canvas& canvas, const render::View& view, const Map& map,
                   const std::vector<const Landmark*>& landmarks);

/// The picture's ground: the shoulder most roads have, lightened so roads and labels stand out.
render::Rgb groundColor(const Map& map);

}  // namespace mapnav
