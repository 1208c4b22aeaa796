// GeoJSON reading, before projection: a FeatureCollection's text read into RawFeatures (each
// feature's lon/lat geometry, the members of its properties that mapnav interprets for its kind, the
// rest kept as they are; a road's id from its street's name when it gives none) and its "mapnav"
// member (the map's name, origin and surfaces). Issues point into the file. geojson.cpp projects
// the features and builds the map from them (importGeoJson), and writes GeoJSON (exportGeoJson).
#include "geojson_internal.h"

#include <cctype>
#include <cmath>

#include "map_json_internal.h"
#include "mapnav/map/map_io.h"

namespace mapnav::geojson {

namespace {

const std::set<std::string, std::less<>>& interpretedMembers(RawFeature::Kind kind) {
  switch (kind) {
    case RawFeature::Kind::Road: return kRoadMembers;
    case RawFeature::Kind::Landmark: return kLandmarkMembers;
    case RawFeature::Kind::Point:
    case RawFeature::Kind::Polygon: break;
  }
  return kIntersectionMembers;
}

std::optional<LatLon> readPosition(const Json& value, const std::string& pointer, Issues& issues) {
  if (!value.is_array() || value.size() < 2 || value.size() > 3) {
    addIssue(issues, Severity::Error, "geojson.position", pointer, "expected a position [lon, lat] or [lon, lat, alt]");
    return std::nullopt;
  }
  const auto lon = readNumber(value[0], pointerJoin(pointer, std::size_t{0}), issues, -180, 180);
  const auto lat = readNumber(value[1], pointerJoin(pointer, std::size_t{1}), issues, -90, 90);
  if (value.size() == 3) readNumber(value[2], pointerJoin(pointer, std::size_t{2}), issues);
  if (!lon || !lat) return std::nullopt;
  return LatLon{*lat, *lon};
}

std::optional<std::vector<LatLon>> readPositions(const Json& value, const std::string& pointer, Issues& issues,
                                                 std::size_t min_count) {
  if (!value.is_array() || value.size() < min_count) {
    addIssue(issues, Severity::Error, "geojson.position", pointer,
             "expected an array of at least " + std::to_string(min_count) + " positions");
    return std::nullopt;
  }
  std::vector<LatLon> out;
  bool ok = true;
  for (std::size_t i = 0; i < value.size(); ++i) {
    const auto p = readPosition(value[i], pointerJoin(pointer, i), issues);
    if (p) out.push_back(*p);
    ok = ok && p.has_value();
  }
  if (!ok) return std::nullopt;
  return out;
}

// Property values: strings, or numbers for ids (QGIS writes integer ids).
std::optional<std::string> stringProperty(const Json& properties, const std::string& pointer, const char* key,
                                          Issues& issues, bool allow_number = false) {
  const auto it = properties.find(key);
  if (it == properties.end() || it->is_null()) return std::nullopt;
  if (it->is_string()) return it->get<std::string>();
  if (allow_number && it->is_number_integer()) return std::to_string(it->get<long long>());
  addIssue(issues, Severity::Error, "schema.type", pointerJoin(pointer, key),
           "expected a string, got " + std::string(jsonTypeName(*it)));
  return std::nullopt;
}

std::optional<double> numberProperty(const Json& properties, const std::string& pointer, const char* key, Issues& issues) {
  const auto it = properties.find(key);
  if (it == properties.end() || it->is_null()) return std::nullopt;
  return readNumber(*it, pointerJoin(pointer, key), issues);
}

// A map id from a street's name: ASCII letters, digits, '_' and '-' (German umlauts and ß spelt out,
// every other character '_'), starting with a letter, at most 64 characters: "Rintheimer Querallee"
// -> "Rintheimer_Querallee", "Veilchenstraße" -> "Veilchenstrasse".
std::string idFromName(const std::string& name) {
  static const std::vector<std::pair<std::string, std::string>> spelt = {
      {"\xc3\x9f", "ss"}, {"\xc3\xa4", "ae"}, {"\xc3\xb6", "oe"}, {"\xc3\xbc", "ue"},
      {"\xc3\x84", "Ae"}, {"\xc3\x96", "Oe"}, {"\xc3\x9c", "Ue"}};
  std::string out;
  for (std::size_t i = 0; i < name.size();) {
    bool done = false;
    for (const auto& [utf8, ascii] : spelt)
      if (name.compare(i, utf8.size(), utf8) == 0) {
        out += ascii;
        i += utf8.size();
        done = true;
        break;
      }
    if (done) continue;
    const unsigned char c = static_cast<unsigned char>(name[i]);
    if (c >= 0x80) {  // another UTF-8 character: one '_' for all its bytes
      out += '_';
      ++i;
      while (i < name.size() && (static_cast<unsigned char>(name[i]) & 0xC0) == 0x80) ++i;
      continue;
    }
    out += std::isalnum(c) || c == '-' || c == '_' ? static_cast<char>(c) : '_';
    ++i;
  }
  if (out.empty() || !std::isalpha(static_cast<unsigned char>(out.front()))) out = "R_" + out;
  return out.substr(0, 56);  // room for a piece's suffix
}

// The feature's geometry into `raw` (its kind: a road, a point, a polygon; and its lon/lat).
// False, with issues, when it is not a geometry mapnav reads.
bool readGeometry(JsonObject& feature, RawFeature& raw, Issues& issues) {
  const Json* geometry = feature.member("geometry", true);
  if (geometry == nullptr) return false;
  JsonObject g(*geometry, feature.pointer("geometry"), issues);
  const auto gtype = g.string("type");
  const Json* coordinates = g.member("coordinates", true);
  if (!gtype || coordinates == nullptr) return false;
  const std::string cptr = g.pointer("coordinates");
  if (*gtype == "LineString") {
    raw.kind = RawFeature::Kind::Road;
    auto line = readPositions(*coordinates, cptr, issues, 2);
    if (!line) return false;
    raw.lines.push_back(std::move(*line));
  } else if (*gtype == "MultiLineString") {  // a street drawn in parts: a road per part
    raw.kind = RawFeature::Kind::Road;
    if (!coordinates->is_array() || coordinates->empty()) {
      addIssue(issues, Severity::Error, "geojson.position", cptr, "expected an array of line strings");
      return false;
    }
    for (std::size_t k = 0; k < coordinates->size(); ++k) {
      auto line = readPositions((*coordinates)[k], pointerJoin(cptr, k), issues, 2);
      if (!line) return false;
      raw.lines.push_back(std::move(*line));
    }
  } else if (*gtype == "Point") {
    raw.kind = RawFeature::Kind::Point;
    auto p = readPosition(*coordinates, cptr, issues);
    if (!p) return false;
    raw.coordinates = {*p};
  } else if (*gtype == "Polygon") {
    raw.kind = RawFeature::Kind::Polygon;
    if (!coordinates->is_array() || coordinates->empty()) {
      addIssue(issues, Severity::Error, "geojson.position", cptr, "expected an array of linear rings");
      return false;
    }
    auto ring = readPositions((*coordinates)[0], pointerJoin(cptr, std::size_t{0}), issues, 4);
    if (!ring) return false;
    if (ring->front().lat != ring->back().lat || ring->front().lon != ring->back().lon) {
      addIssue(issues, Severity::Error, "geojson.position", pointerJoin(cptr, std::size_t{0}),
               "a linear ring must end at its first position (RFC 7946, 3.1.6)");
      return false;
    }
    ring->pop_back();
    raw.coordinates = std::move(*ring);
  } else {
    addIssue(issues, Severity::Error, "geojson.unsupported_geometry", g.pointer("type"),
             "geometry \"" + *gtype + "\" is not supported: roads are LineString or MultiLineString, intersections "
             "Point or Polygon, landmarks Point");
    return false;
  }
  return true;
}

// The members a road or an intersection feature's properties may carry (read on both kinds, as
// they always were: a Point's `width` must be a number too).
void readNetworkMembers(const Json& p, const std::string& pptr, RawFeature& raw, Issues& issues) {
  raw.id = stringProperty(p, pptr, "id", issues, true);
  raw.kind_name = stringProperty(p, pptr, "kind", issues);
  raw.from = stringProperty(p, pptr, "from", issues, true);
  raw.to = stringProperty(p, pptr, "to", issues, true);
  raw.surface = stringProperty(p, pptr, "surface", issues);
  raw.left = stringProperty(p, pptr, "left", issues);
  raw.right = stringProperty(p, pptr, "right", issues);
  raw.width = numberProperty(p, pptr, "width", issues);
  raw.cost_factor = numberProperty(p, pptr, "cost_factor", issues);
  raw.position_sigma_m = numberProperty(p, pptr, "position_sigma_m", issues);
  if (const auto it = p.find("oneway"); it != p.end() && !it->is_null()) {
    if (it->is_boolean()) {
      raw.oneway = it->get<bool>();
    } else {
      addIssue(issues, Severity::Error, "schema.type", pointerJoin(pptr, "oneway"), "expected true or false");
    }
  }
  if (const auto layer = numberProperty(p, pptr, "layer", issues)) {
    if (*layer == std::floor(*layer) && std::abs(*layer) <= 10) {
      raw.layer = static_cast<int>(*layer);
    } else {
      addIssue(issues, Severity::Error, "schema.range", pointerJoin(pptr, "layer"), "expected an integer in [-10, 10]");
    }
  }
  if (const auto structure = stringProperty(p, pptr, "structure", issues)) {
    raw.structure = roadStructureFromString(*structure);
    if (!raw.structure) {
      addIssue(issues, Severity::Error, "schema.enum", pointerJoin(pptr, "structure"),
               "unknown road structure \"" + *structure + "\"; expected one of none, bridge, tunnel");
    }
  }
  if (const auto it = p.find("center"); it != p.end() && !it->is_null()) {
    raw.center = readPosition(*it, pointerJoin(pptr, "center"), issues);
  }
  if (!raw.id && raw.kind == RawFeature::Kind::Road) {
    if (const auto name = stringProperty(p, pptr, "name", issues)) {
      raw.id = idFromName(*name);
      raw.id_from_name = true;
    }
  }
}

// The members of a landmark's properties: its kind (`landmark`), id, size and road.
void readLandmarkMembers(const Json& p, const std::string& pptr, RawFeature& raw, Issues& issues) {
  if (const auto kind = stringProperty(p, pptr, "landmark", issues)) {
    raw.landmark = readLandmarkKind(*kind, pointerJoin(pptr, "landmark"), issues);
  }
  raw.id = stringProperty(p, pptr, "id", issues, true);
  raw.radius = numberProperty(p, pptr, "radius", issues);
  raw.height = numberProperty(p, pptr, "height", issues);
  raw.road = stringProperty(p, pptr, "road", issues, true);
}

// A feature's properties into `raw`: the members mapnav interprets for its kind, and the rest kept
// as they are. A Point with a `landmark` property is a landmark. False, with issues, when a member
// mapnav interprets is wrong.
bool readProperties(JsonObject& feature, RawFeature& raw, Issues& issues) {
  const Json* properties = feature.member("properties", false);
  const std::string pptr = feature.pointer("properties");
  if (properties == nullptr || properties->is_null()) return true;
  if (!properties->is_object()) {
    addIssue(issues, Severity::Error, "schema.type", pptr, "expected an object or null");
    return false;
  }
  const Json& p = *properties;
  if (const auto it = p.find("landmark"); it != p.end() && !it->is_null()) {
    if (raw.kind != RawFeature::Kind::Point) {
      addIssue(issues, Severity::Error, "geojson.unsupported_geometry", feature.pointer("geometry") + "/type",
               "a landmark (properties.landmark) is a Point feature");
      return false;
    }
    raw.kind = RawFeature::Kind::Landmark;
  }
  const std::size_t before = issues.size();
  if (raw.kind == RawFeature::Kind::Landmark) {
    readLandmarkMembers(p, pptr, raw, issues);
  } else {
    readNetworkMembers(p, pptr, raw, issues);
  }
  if (issues.size() != before) return false;
  const auto& interpreted = interpretedMembers(raw.kind);
  for (auto it = p.begin(); it != p.end(); ++it) {
    if (!interpreted.contains(it.key())) raw.extra.emplace(it.key(), propertyFromJson(*it));
  }
  if (const auto it = p.find(kShadowed); it != p.end() && it->is_object()) {
    for (auto k = it->begin(); k != it->end(); ++k) raw.extra.emplace(k.key(), propertyFromJson(*k));
  } else if (it != p.end()) {
    addIssue(issues, Severity::Error, "schema.type", pointerJoin(pptr, kShadowed), "expected an object");
    return false;
  }
  return true;
}

std::optional<RawFeature> readFeature(const Json& value, const std::string& pointer, Issues& issues) {
  JsonObject feature(value, pointer, issues);
  if (!feature.isObject()) return std::nullopt;
  const auto type = feature.string("type");
  if (type && *type != "Feature") {
    addIssue(issues, Severity::Error, "geojson.type", feature.pointer("type"), "expected \"Feature\", got \"" + *type + "\"");
    return std::nullopt;
  }
  RawFeature raw;
  raw.pointer = pointer;
  if (!readGeometry(feature, raw, issues) || !readProperties(feature, raw, issues)) return std::nullopt;
  if (!raw.id && raw.kind == RawFeature::Kind::Road) {  // RFC 7946's feature "id": a street's name in many exports
    if (const auto it = value.find("id"); it != value.end() && (it->is_string() || it->is_number_integer())) {
      const std::string name = it->is_string() ? it->get<std::string>() : std::to_string(it->get<long long>());
      raw.id = idFromName(name);
      raw.id_from_name = true;
      if (!raw.extra.contains("name")) raw.extra.emplace("name", name);
    }
  }
  return raw;
}

}  // namespace

// The FeatureCollection's features as read, and what its "mapnav" member says (the map's name and
// surfaces into `map`, the local frame's origin into `file_origin`, its position_sigma_m into
// `file_sigma`). Nothing when the document is not a FeatureCollection with a "features" array; bad
// features are left out with their issues.
std::optional<std::vector<RawFeature>> readFeatureCollection(std::string_view text, Issues& issues, MapData& map,
                                                             std::optional<GeoOrigin>& file_origin, std::optional<double>& file_sigma) {
  const auto json = parseJson(text, issues);
  if (!json) return std::nullopt;
  if (!json->is_object()) {
    addIssue(issues, Severity::Error, "schema.type", "", "expected a GeoJSON FeatureCollection object");
    return std::nullopt;
  }
  const Json& doc = *json;
  if (!doc.contains("type") || doc["type"] != "FeatureCollection") {
    addIssue(issues, Severity::Error, "geojson.type", "/type", "expected \"type\": \"FeatureCollection\"");
    return std::nullopt;
  }
  if (const auto it = doc.find("mapnav"); it != doc.end()) {
    JsonObject meta(*it, "/mapnav", issues);
    if (const auto format = meta.string("format", false); format && *format != kMapFormat) {
      addIssue(issues, Severity::Error, "schema.format", "/mapnav/format", "unknown format \"" + *format + "\"");
    }
    if (const auto name = meta.string("name", false)) map.name = *name;
    if (const Json* o = meta.member("origin", false)) file_origin = readOrigin(*o, "/mapnav/origin", issues);
    file_sigma = meta.number("position_sigma_m", false);
    if (auto s = readSurfaces(meta.member("surfaces", false), "/mapnav/surfaces", issues)) map.surfaces = std::move(*s);
    meta.rejectUnknownMembers();
  }
  const auto features_it = doc.find("features");
  if (features_it == doc.end() || !features_it->is_array()) {
    addIssue(issues, Severity::Error, "schema.required", "", "a FeatureCollection needs a \"features\" array");
    return std::nullopt;
  }
  std::vector<RawFeature> raws;
  for (std::size_t k = 0; k < features_it->size(); ++k) {
    if (auto raw = readFeature((*features_it)[k], pointerJoin("/features", k), issues)) raws.push_back(std::move(*raw));
  }
  return raws;
}

}  // namespace mapnav::geojson
