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
  info.landmarks = map.landmarks().size();
  for (const Landmark& l : map.landmarks()) ++info.landmarks_by_kind[std::string(toString(l.kind))];
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

// "roads:         4 (asphalt 1, concrete 3)": the label, the total, and the counts by name.
std::string countsLine(const std::string& label, std::size_t total, const std::map<std::string, std::size_t>& by) {
  std::string out = label + std::to_string(total);
  std::string sep = " (";
  for (const auto& [name, n] : by) {
    out += sep + name + " " + std::to_string(n);
    sep = ", ";
  }
  return out + (by.empty() ? "" : ")") + "\n";
}
}  // namespace

std::string toText(const MapInfo& info) {
  std::ostringstream out;
  out << "name:          " << info.name << "\n";
  out << countsLine("intersections: ", info.intersections, info.intersections_by_kind);
  out << countsLine("roads:         ", info.roads, info.roads_by_surface);
  out << countsLine("landmarks:     ", info.landmarks, info.landmarks_by_kind);
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
  j["landmarks"] = info.landmarks;
  j["landmarks_by_kind"] = Json(info.landmarks_by_kind);
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
