#include <cmath>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/core/json.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/map/map_io.h"
#include "map_json_internal.h"

namespace mapnav {

// ---- reading ----------------------------------------------------------------------------------

void reportSuppressed(Issues& issues, const std::string& pointer, std::size_t bad) {
  if (bad <= kMaxIssuesPerArray) return;
  addIssue(issues, Severity::Error, "schema.too_many_errors", pointer,
           std::to_string(bad - kMaxIssuesPerArray) + " more bad elements in this array are not listed");
}

std::optional<Vec2> readPoint(const Json& value, const std::string& pointer, Issues& issues) {
  if (!value.is_array() || value.size() != 2) {
    addIssue(issues, Severity::Error, "schema.type", pointer,
             "expected a point [x, y], got " +
                 (value.is_array() ? "an array of " + std::to_string(value.size()) : std::string(jsonTypeName(value))));
    return std::nullopt;
  }
  const auto x = readNumber(value[0], pointerJoin(pointer, std::size_t{0}), issues);
  const auto y = readNumber(value[1], pointerJoin(pointer, std::size_t{1}), issues);
  if (!x || !y) return std::nullopt;
  return Vec2(*x, *y);
}

std::optional<std::vector<Vec2>> readPoints(const Json* value, const std::string& pointer, Issues& issues) {
  if (value == nullptr) return std::nullopt;
  if (!value->is_array()) {
    addIssue(issues, Severity::Error, "schema.type", pointer,
             "expected an array of points, got " + std::string(jsonTypeName(*value)));
    return std::nullopt;
  }
  std::vector<Vec2> points;
  points.reserve(value->size());
  bool ok = true;
  std::size_t bad = 0;
  for (std::size_t k = 0; k < value->size(); ++k) {
    Issues found;
    const auto p = readPoint((*value)[k], pointerJoin(pointer, k), found);
    if (p) {
      points.push_back(*p);
      continue;
    }
    ok = false;
    if (++bad <= kMaxIssuesPerArray) issues.insert(issues.end(), found.begin(), found.end());
  }
  reportSuppressed(issues, pointer, bad);
  if (!ok) return std::nullopt;
  return points;
}

std::optional<Vec3> readColor(const Json* value, const std::string& pointer, Issues& issues) {
  if (value == nullptr) return std::nullopt;
  if (!value->is_array() || value->size() != 3) {
    addIssue(issues, Severity::Error, "schema.type", pointer, "expected [r, g, b] (three numbers 0-255)");
    return std::nullopt;
  }
  Vec3 c;
  bool ok = true;
  for (std::size_t k = 0; k < 3; ++k) {
    const auto v = readNumber((*value)[k], pointerJoin(pointer, k), issues, 0, 255);
    if (v) c[static_cast<Eigen::Index>(k)] = *v;
    ok = ok && v.has_value();
  }
  if (!ok) return std::nullopt;
  return c;
}

std::optional<Appearance> readAppearance(const Json& value, const std::string& pointer, Issues& issues) {
  JsonObject object(value, pointer, issues);
  if (!object.isObject()) return std::nullopt;
  const auto rgb = readColor(object.member("rgb", true), object.pointer("rgb"), issues);
  const auto spread = readColor(object.member("spread", true), object.pointer("spread"), issues);
  object.rejectUnknownMembers();
  if (!rgb || !spread) return std::nullopt;
  return Appearance{*rgb, *spread};
}

std::optional<GeoOrigin> readOrigin(const Json& value, const std::string& pointer, Issues& issues) {
  JsonObject object(value, pointer, issues);
  const auto lat = object.number("lat", true, -90, 90);
  const auto lon = object.number("lon", true, -180, 180);
  const auto alt = object.number("alt", false, -1e5, 1e5);
  object.rejectUnknownMembers();
  if (!lat || !lon) return std::nullopt;
  return GeoOrigin{*lat, *lon, alt.value_or(0.0)};
}

std::optional<std::vector<std::pair<std::string, Appearance>>> readSurfaces(const Json* value, const std::string& pointer,
                                                                         Issues& issues) {
  if (value == nullptr) return std::nullopt;
  if (!value->is_object()) {
    addIssue(issues, Severity::Error, "schema.type", pointer, "expected an object of surfaces, got " + std::string(jsonTypeName(*value)));
    return std::nullopt;
  }
  std::vector<std::pair<std::string, Appearance>> surfaces;
  for (auto it = value->begin(); it != value->end(); ++it) {
    if (it.key().rfind("x-", 0) == 0) continue;
    if (auto a = readAppearance(*it, pointerJoin(pointer, it.key()), issues)) surfaces.emplace_back(it.key(), *a);
  }
  return surfaces;
}

namespace {

/// "properties": {"name": any JSON value, ...}; nothing when absent.
Properties readProperties(JsonObject& object, Issues& issues) {
  Properties out;
  const Json* value = object.member("properties", false);
  if (value == nullptr) return out;
  if (!value->is_object()) {
    addIssue(issues, Severity::Error, "schema.type", object.pointer("properties"),
             "expected an object, got " + std::string(jsonTypeName(*value)));
    return out;
  }
  for (auto it = value->begin(); it != value->end(); ++it) out.emplace(it.key(), propertyFromJson(*it));
  return out;
}

Json propertiesToJson(const Properties& properties) {
  Json out = Json::object();
  for (const auto& [key, value] : properties) out[key] = propertyToJson(value);
  return out;
}

}  // namespace

PropertyValue propertyFromJson(const Json& value) {
  return value.is_string() ? PropertyValue(value.get<std::string>()) : PropertyValue::json(value.dump());
}

Json propertyToJson(const PropertyValue& value) {
  if (!value.is_json) return value.text;
  Json parsed = Json::parse(value.text, nullptr, false);
  if (parsed.is_discarded()) throw InvalidInput("a property value marked as JSON is not JSON: " + value.text);
  return parsed;
}

std::optional<LandmarkKind> readLandmarkKind(const std::string& text, const std::string& pointer, Issues& issues) {
  const auto kind = landmarkKindFromString(text);
  if (!kind) {
    std::string allowed;
    for (LandmarkKind k : allLandmarkKinds()) allowed += std::string(allowed.empty() ? "" : ", ") + std::string(toString(k));
    addIssue(issues, Severity::Error, "schema.enum", pointer, "unknown landmark kind \"" + text + "\"; expected one of " + allowed);
  }
  return kind;
}

namespace {

std::optional<Intersection> readIntersection(const Json& value, const std::string& pointer, Issues& issues) {
  JsonObject object(value, pointer, issues);
  if (!object.isObject()) return std::nullopt;
  Intersection x;
  const auto id = object.string("id");
  const auto kind = object.string("kind");
  std::optional<IntersectionKind> parsed_kind;
  if (kind) {
    parsed_kind = intersectionKindFromString(*kind);
    if (!parsed_kind) {
      std::string allowed;
      for (IntersectionKind k : allIntersectionKinds()) allowed += std::string(allowed.empty() ? "" : ", ") + std::string(toString(k));
      addIssue(issues, Severity::Error, "schema.enum", object.pointer("kind"),
               "unknown intersection kind \"" + *kind + "\"; expected one of " + allowed);
    }
  }
  const Json* position = object.member("position", true);
  const auto point = position ? readPoint(*position, object.pointer("position"), issues) : std::nullopt;
  std::optional<std::vector<Vec2>> shape;
  const Json* shape_json = object.member("shape", false);
  if (shape_json) shape = readPoints(shape_json, object.pointer("shape"), issues);
  x.properties = readProperties(object, issues);
  object.rejectUnknownMembers();
  if (!id || !parsed_kind || !point || (shape_json && !shape)) return std::nullopt;
  x.id = *id;
  x.kind = *parsed_kind;
  x.position = *point;
  x.shape = shape;
  return x;
}

/// "layer": an integer in [-10, 10] (OSM's range; default 0).
std::optional<int> readLayer(JsonObject& object) {
  const auto layer = object.number("layer", false, -10, 10);
  if (!layer) return std::nullopt;
  if (*layer != std::floor(*layer)) {
    addIssue(object.issues(), Severity::Error, "schema.type", object.pointer("layer"),
             "expected an integer, got " + numberText(*layer));
    return std::nullopt;
  }
  return static_cast<int>(*layer);
}

/// "structure": "none", "bridge" or "tunnel" (default none).
std::optional<RoadStructure> readStructure(JsonObject& object) {
  const auto text = object.string("structure", false);
  if (!text) return std::nullopt;
  const auto structure = roadStructureFromString(*text);
  if (!structure) {
    addIssue(object.issues(), Severity::Error, "schema.enum", object.pointer("structure"),
             "unknown road structure \"" + *text + "\"; expected one of none, bridge, tunnel");
  }
  return structure;
}

std::optional<Road> readRoad(const Json& value, const std::string& pointer, Issues& issues) {
  JsonObject object(value, pointer, issues);
  if (!object.isObject()) return std::nullopt;
  const auto id = object.string("id");
  const auto from = object.string("from");
  const auto to = object.string("to");
  const auto centerline = readPoints(object.member("centerline", true), object.pointer("centerline"), issues);
  const auto width = object.number("width");
  const auto surface = object.string("surface");
  const auto left = object.string("left");
  const auto right = object.string("right");
  const auto oneway = object.boolean("oneway", false);
  const auto cost_factor = object.number("cost_factor", false);
  const auto layer = readLayer(object);
  const auto structure = readStructure(object);
  const auto position_sigma = object.number("position_sigma_m", false);
  Properties properties = readProperties(object, issues);
  object.rejectUnknownMembers();
  const bool optional_ok = (oneway || !object.has("oneway")) && (cost_factor || !object.has("cost_factor")) &&
                           (layer || !object.has("layer")) && (structure || !object.has("structure")) &&
                           (position_sigma || !object.has("position_sigma_m"));
  if (!id || !from || !to || !centerline || !width || !surface || !left || !right || !optional_ok) return std::nullopt;
  Road road;
  road.id = *id;
  road.from = *from;
  road.to = *to;
  road.centerline = Polyline2(*centerline);
  road.width = *width;
  road.surface = *surface;
  road.left = *left;
  road.right = *right;
  road.oneway = oneway.value_or(false);
  road.cost_factor = cost_factor.value_or(1.0);
  road.layer = layer.value_or(0);
  road.structure = structure.value_or(RoadStructure::None);
  road.position_sigma_m = position_sigma;
  road.properties = std::move(properties);
  return road;
}

/// A landmark: its kind, position, and the kind's size unless the file gives one.
std::optional<Landmark> readLandmark(const Json& value, const std::string& pointer, Issues& issues) {
  JsonObject object(value, pointer, issues);
  if (!object.isObject()) return std::nullopt;
  const auto id = object.string("id");
  const auto kind = object.string("kind");
  std::optional<LandmarkKind> parsed_kind;
  if (kind) parsed_kind = readLandmarkKind(*kind, object.pointer("kind"), issues);
  const Json* position = object.member("position", true);
  const auto point = position ? readPoint(*position, object.pointer("position"), issues) : std::nullopt;
  const auto radius = object.number("radius", false);
  const auto height = object.number("height", false);
  const auto road = object.string("road", false);
  Properties properties = readProperties(object, issues);
  object.rejectUnknownMembers();
  const bool optional_ok = (radius || !object.has("radius")) && (height || !object.has("height")) && (road || !object.has("road"));
  if (!id || !parsed_kind || !point || !optional_ok) return std::nullopt;
  const LandmarkSize size = defaultLandmarkSize(*parsed_kind);
  return Landmark{*id, *parsed_kind, *point, radius.value_or(size.radius_m), height.value_or(size.height_m),
                  road.value_or(""), std::move(properties)};
}

template <typename T, typename Reader>
void readArray(const Json* value, const std::string& pointer, Issues& issues, std::vector<T>& out, Reader read) {
  if (value == nullptr) return;
  if (!value->is_array()) {
    addIssue(issues, Severity::Error, "schema.type", pointer, "expected an array, got " + std::string(jsonTypeName(*value)));
    return;
  }
  out.reserve(value->size());
  std::size_t bad = 0;
  for (std::size_t i = 0; i < value->size(); ++i) {
    Issues found;
    if (auto item = read((*value)[i], pointerJoin(pointer, i), found)) out.push_back(std::move(*item));
    if (found.empty()) continue;
    if (hasErrors(found)) ++bad;
    if (bad <= kMaxIssuesPerArray) issues.insert(issues.end(), found.begin(), found.end());
  }
  reportSuppressed(issues, pointer, bad);
}

}  // namespace

std::optional<MapData> parseMap(std::string_view text, Issues& issues) {
  const std::size_t before = countSeverity(issues, Severity::Error);
  const auto json = parseJson(text, issues);
  if (!json) return std::nullopt;
  JsonObject top(*json, "", issues);
  if (!top.isObject()) return std::nullopt;

  MapData map;
  if (const auto format = top.string("format")) {
    if (*format != kMapFormat) {
      addIssue(issues, Severity::Error, "schema.format", "/format",
               "unknown format \"" + *format + "\"; expected \"" + std::string(kMapFormat) + "\"");
    }
  }
  map.name = top.string("name").value_or("");
  if (const Json* schema = top.member("$schema", false)) {
    if (schema->is_string()) {
      map.schema = schema->get<std::string>();
    } else {
      addIssue(issues, Severity::Error, "schema.type", "/$schema", "expected a string");
    }
  }
  if (const Json* origin = top.member("origin", false)) map.origin = readOrigin(*origin, "/origin", issues);
  map.position_sigma_m = top.number("position_sigma_m", false).value_or(0.0);
  if (auto surfaces = readSurfaces(top.member("surfaces", true), "/surfaces", issues)) map.surfaces = std::move(*surfaces);
  readArray(top.member("intersections", true), "/intersections", issues, map.intersections, readIntersection);
  readArray(top.member("roads", true), "/roads", issues, map.roads, readRoad);
  readArray(top.member("landmarks", false), "/landmarks", issues, map.landmarks, readLandmark);
  top.rejectUnknownMembers();
  if (countSeverity(issues, Severity::Error) != before) return std::nullopt;
  return map;
}

std::optional<Map> loadMap(const std::filesystem::path& path, Issues& issues, const ValidationOptions& options) {
  const std::string text = readFile(path);
  auto data = parseMap(text, issues);
  if (!data) return std::nullopt;
  return buildMap(std::move(*data), path.string(), issues, options);
}

std::optional<Map> buildMap(MapData data, const std::string& source, Issues& issues, const ValidationOptions& options) {
  try {
    Map map(std::move(data), source, options);
    issues.insert(issues.end(), map.warnings().begin(), map.warnings().end());
    return map;
  } catch (const ValidationError& e) {
    issues.insert(issues.end(), e.issues().begin(), e.issues().end());
    return std::nullopt;
  }
}

Map loadMap(const std::filesystem::path& path, const ValidationOptions& options) {
  Issues issues;
  auto map = loadMap(path, issues, options);
  if (!map) throw ValidationError(path.string(), std::move(issues));
  return std::move(*map);
}

// ---- writing ----------------------------------------------------------------------------------

Json pointToJson(const Vec2& p) { return Json::array({p.x(), p.y()}); }

Json pointsToJson(const std::vector<Vec2>& points) {
  Json out = Json::array();
  for (const Vec2& p : points) out.push_back(pointToJson(p));
  return out;
}

Json surfacesToJson(const std::vector<std::pair<std::string, Appearance>>& surfaces) {
  Json out = Json::object();
  for (const auto& [name, a] : surfaces) {
    out[name] = {{"rgb", {a.rgb.x(), a.rgb.y(), a.rgb.z()}}, {"spread", {a.spread.x(), a.spread.y(), a.spread.z()}}};
  }
  return out;
}

Json originToJson(const GeoOrigin& o) { return {{"lat", o.lat}, {"lon", o.lon}, {"alt", o.alt}}; }

std::string mapToJson(const MapData& map) {
  Json doc = Json::object();
  if (!map.schema.empty()) doc["$schema"] = map.schema;
  doc["format"] = kMapFormat;
  doc["name"] = map.name;
  if (map.origin) doc["origin"] = originToJson(*map.origin);
  if (map.position_sigma_m != 0) doc["position_sigma_m"] = map.position_sigma_m;
  doc["surfaces"] = surfacesToJson(map.surfaces);
  Json intersections = Json::array();
  for (const Intersection& x : map.intersections) {
    Json j = {{"id", x.id}, {"kind", toString(x.kind)}, {"position", pointToJson(x.position)}};
    if (x.shape) j["shape"] = pointsToJson(*x.shape);
    if (!x.properties.empty()) j["properties"] = propertiesToJson(x.properties);
    intersections.push_back(std::move(j));
  }
  doc["intersections"] = std::move(intersections);
  Json roads = Json::array();
  for (const Road& r : map.roads) {
    Json j = {{"id", r.id}, {"from", r.from}, {"to", r.to}, {"width", r.width}, {"surface", r.surface},
              {"left", r.left}, {"right", r.right}};
    if (r.oneway) j["oneway"] = true;
    if (r.cost_factor != 1.0) j["cost_factor"] = r.cost_factor;
    if (r.layer != 0) j["layer"] = r.layer;
    if (r.structure != RoadStructure::None) j["structure"] = toString(r.structure);
    if (r.position_sigma_m) j["position_sigma_m"] = *r.position_sigma_m;
    if (!r.properties.empty()) j["properties"] = propertiesToJson(r.properties);
    j["centerline"] = pointsToJson(r.centerline.points());
    roads.push_back(std::move(j));
  }
  doc["roads"] = std::move(roads);
  if (!map.landmarks.empty()) {
    Json landmarks = Json::array();
    for (const Landmark& l : map.landmarks) {
      Json j = {{"id", l.id}, {"kind", toString(l.kind)}, {"position", pointToJson(l.position)}, {"radius", l.radius},
                {"height", l.height}};
      if (!l.road.empty()) j["road"] = l.road;
      if (!l.properties.empty()) j["properties"] = propertiesToJson(l.properties);
      landmarks.push_back(std::move(j));
    }
    doc["landmarks"] = std::move(landmarks);
  }
  return dumpJson(doc);
}

void saveMap(const MapData& map, const std::filesystem::path& path) { writeFileAtomic(path, mapToJson(map)); }

}  // namespace mapnav
