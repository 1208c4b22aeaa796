#include "mapnav/map/info.h"

#include <cstdio>
#include <sstream>

#include "mapnav/core/json.h"

namespace mapnav {

MapInfo describeMap(const Map& map) {
  MapInfo info;
  info.name = map.name();
  info.intersections = map.intersections().size();
  info.roads = map.roads().size();
  for (const Intersection& x : map.intersections()) ++info.intersections_by_kind[std::string(toString(x.kind))];
  for (const Road& r : map.roads()) {
    ++info.roads_by_surface[r.surface];
    info.total_length_m += r.centerline.length();
    info.paved_area_m2 += r.centerline.length() * r.width;
  }
  info.bounds = map.bounds();
  info.components = map.components().size();
  info.origin = map.data().origin;
  return info;
}

namespace {
std::string fixed(double x, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, x);
  return buffer;
}
}  // namespace

std::string toText(const MapInfo& info) {
  std::ostringstream out;
  out << "name:          " << info.name << "\n";
  out << "intersections: " << info.intersections;
  std::string sep = " (";
  for (const auto& [kind, n] : info.intersections_by_kind) {
    out << sep << kind << " " << n;
    sep = ", ";
  }
  out << (info.intersections_by_kind.empty() ? "" : ")") << "\n";
  out << "roads:         " << info.roads;
  sep = " (";
  for (const auto& [surface, n] : info.roads_by_surface) {
    out << sep << surface << " " << n;
    sep = ", ";
  }
  out << (info.roads_by_surface.empty() ? "" : ")") << "\n";
  out << "total length:  " << fixed(info.total_length_m, 1) << " m\n";
  out << "paved area:    " << fixed(info.paved_area_m2, 1) << " m²\n";
  if (!info.bounds.isEmpty()) {
    out << "bounds:        x " << fixed(info.bounds.min().x(), 1) << " .. " << fixed(info.bounds.max().x(), 1)
        << " m, y " << fixed(info.bounds.min().y(), 1) << " .. " << fixed(info.bounds.max().y(), 1) << " m ("
        << fixed(info.bounds.sizes().x(), 1) << " × " << fixed(info.bounds.sizes().y(), 1) << " m)\n";
  }
  out << "components:    " << info.components << (info.components == 1 ? " (connected)" : " (disconnected)") << "\n";
  if (info.origin) {
    out << "origin:        lat " << fixed(info.origin->lat, 7) << ", lon " << fixed(info.origin->lon, 7) << ", alt "
        << fixed(info.origin->alt, 1) << " m\n";
  }
  return out.str();
}

std::string toJson(const MapInfo& info) {
  Json j = Json::object();
  j["name"] = info.name;
  j["intersections"] = info.intersections;
  j["intersections_by_kind"] = Json(info.intersections_by_kind);
  j["roads"] = info.roads;
  j["roads_by_surface"] = Json(info.roads_by_surface);
  j["total_length_m"] = info.total_length_m;
  j["paved_area_m2"] = info.paved_area_m2;
  if (!info.bounds.isEmpty()) {
    j["bounds"] = {{"min", {info.bounds.min().x(), info.bounds.min().y()}},
                   {"max", {info.bounds.max().x(), info.bounds.max().y()}}};
  }
  j["components"] = info.components;
  if (info.origin) j["origin"] = {{"lat", info.origin->lat}, {"lon", info.origin->lon}, {"alt", info.origin->alt}};
  return dumpJson(j);
}

}  // namespace mapnav
