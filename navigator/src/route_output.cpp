#include "mapnav/navigator/route_output.h"

#include <cmath>

#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/map/geodesy.h"

namespace mapnav {

using render::Rgb;
using render::Style;
using render::TextStyle;

render::Canvas renderRoute(const Map& map, const Route& route, const MapRenderOptions& options) {
  MapPicture picture = renderMap(map, options);
  render::Canvas& canvas = picture.canvas;
  const render::View& view = picture.view;
  std::vector<Vec2> line;
  for (const Vec2& p : route.line.points()) line.push_back(view.toPixel(p));
  canvas.polyline(line, Style{std::nullopt, Rgb{255, 255, 255}, 9.0, 0.9, false});
  canvas.polyline(line, Style{std::nullopt, Rgb{30, 90, 230}, 5.0, 1.0, false});
  // The turns, numbered in order, at their intersections.
  int n = 0;
  for (const Leg& leg : route.legs) {
    if (leg.action != LegAction::Turn) continue;
    const Vec2 at = view.toPixel(map.intersection(leg.at).position);
    canvas.circle(at, 9.0, Style{Rgb{30, 90, 230}, Rgb{255, 255, 255}, 1.5, 1.0, false});
    TextStyle number;
    number.size_px = 10;
    number.color = Rgb{255, 255, 255};
    number.bold = true;
    canvas.text(at + Vec2(0, 5), std::to_string(++n), number);
  }
  if (!route.line.empty()) {
    canvas.circle(view.toPixel(route.line.front()), 8.0, Style{Rgb{20, 160, 60}, Rgb{255, 255, 255}, 2.0, 1.0, false});
    canvas.circle(view.toPixel(route.line.back()), 8.0, Style{Rgb{210, 30, 30}, Rgb{255, 255, 255}, 2.0, 1.0, false});
  }
  TextStyle caption;
  caption.size_px = 14;
  caption.anchor = render::Anchor::End;
  caption.halo = Rgb{255, 255, 255};
  char text[160];
  std::snprintf(text, sizeof text, "route %s to %s: %.1f m, %zu turns", toString(route.from).c_str(),
                toString(route.to).c_str(), route.length_m, route.intersections.size());
  // Bottom right, across from the scale bar: the top left holds the map's title, which a long
  // route caption would run into (seen on a 660-road OSM import).
  canvas.text(Vec2(canvas.width() - options.margin_px, canvas.height() - 12), text, caption);
  return std::move(picture.canvas);
}

std::string routeToGeoJson(const Map& map, const Route& route) {
  if (!map.data().origin) {
    throw InvalidInput("map \"" + map.name() + "\" has no geodetic origin, so the route cannot be written in lon/lat");
  }
  const LocalFrame frame(*map.data().origin);
  auto position = [&](const Vec2& p) {
    const LatLon g = frame.toGeodetic(p);
    return Json::array({std::round(g.lon * 1e9) / 1e9, std::round(g.lat * 1e9) / 1e9});
  };
  Json coordinates = Json::array();
  for (const Vec2& p : route.line.points()) coordinates.push_back(position(p));
  Json features = Json::array();
  features.push_back({{"type", "Feature"},
                      {"properties", {{"kind", "route"}, {"from", toString(route.from)}, {"to", toString(route.to)},
                                      {"length_m", std::round(route.length_m * 1000) / 1000}, {"dialogue", toDialogue(route)}}},
                      {"geometry", {{"type", "LineString"}, {"coordinates", coordinates}}}});
  if (!route.line.empty()) {
    features.push_back({{"type", "Feature"},
                        {"properties", {{"kind", "start"}, {"position", toString(route.from)}}},
                        {"geometry", {{"type", "Point"}, {"coordinates", position(route.line.front())}}}});
    features.push_back({{"type", "Feature"},
                        {"properties", {{"kind", "goal"}, {"position", toString(route.to)}}},
                        {"geometry", {{"type", "Point"}, {"coordinates", position(route.line.back())}}}});
  }
  return dumpJson(Json{{"type", "FeatureCollection"}, {"features", features}});
}

}  // namespace mapnav
