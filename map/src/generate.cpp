#include "mapnav/map/generate.h"

#include <string>

#include "mapnav/core/error.h"
#include "mapnav/map/geojson.h"

namespace mapnav {

const OptionTable<GridMapOptions>& gridMapOptionTable() {
  using O = GridMapOptions;
  static const OptionTable<O> table =
      OptionTable<O>("GridMapOptions")
          .field("columns", &O::columns, atLeast(2), "intersections per row")
          .field("rows", &O::rows, atLeast(2), "intersections per column")
          .field("spacing_m", &O::spacing_m, "between neighbouring intersections, m")
          .field("width_m", &O::width_m, above(0), "of every road, m")
          .check("spacing_m", [](const O& o) { return o.spacing_m > 2 * o.width_m; }, "> 2 width_m");
  return table;
}

void GridMapOptions::validate() const { gridMapOptionTable().validate(*this); }

MapData makeGridMap(const GridMapOptions& o) {
  o.validate();
  MapData m;
  m.name = "grid " + std::to_string(o.columns) + " x " + std::to_string(o.rows);
  m.surfaces = standardSurfaces();
  auto id = [](const char* prefix, int c, int r) { return prefix + std::to_string(c) + "_" + std::to_string(r); };
  for (int r = 0; r < o.rows; ++r) {
    for (int c = 0; c < o.columns; ++c) {
      const int sides = (c > 0) + (c + 1 < o.columns) + (r > 0) + (r + 1 < o.rows);
      const IntersectionKind kind = sides == 4 ? IntersectionKind::Cross : sides == 3 ? IntersectionKind::T : IntersectionKind::L;
      m.intersections.push_back({id("I", c, r), kind, Vec2(c * o.spacing_m, r * o.spacing_m), std::nullopt});
    }
  }
  auto road = [&](std::string road_id, int c0, int r0, int c1, int r1) {
    Road road;
    road.id = std::move(road_id);
    road.from = id("I", c0, r0);
    road.to = id("I", c1, r1);
    road.centerline = Polyline2({Vec2(c0 * o.spacing_m, r0 * o.spacing_m), Vec2(c1 * o.spacing_m, r1 * o.spacing_m)});
    road.width = o.width_m;
    road.surface = "concrete";
    road.left = road.right = "grass";
    m.roads.push_back(std::move(road));
  };
  for (int r = 0; r < o.rows; ++r) {
    for (int c = 0; c < o.columns; ++c) {
      if (c + 1 < o.columns) road(id("H", c, r), c, r, c + 1, r);
      if (r + 1 < o.rows) road(id("V", c, r), c, r, c, r + 1);
    }
  }
  return m;
}

}  // namespace mapnav
