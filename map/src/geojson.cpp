#include "mapnav/map/geojson.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>
#include <sstream>

#include "map_json_internal.h"
#include "mapnav/core/error.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/geometry/polygon.h"
#include "mapnav/map/geodesy.h"
#include "mapnav/map/map_io.h"

namespace mapnav {

void GeoJsonImportOptions::validate() const {
  auto fail = [](const std::string& what) { throw InvalidInput("GeoJsonImportOptions::" + what); };
  if (!std::isfinite(snap_tolerance_m) || snap_tolerance_m < 0) fail("snap_tolerance_m must be finite and >= 0");
  if (!std::isfinite(default_width_m) || default_width_m <= 0) fail("default_width_m must be finite and > 0");
  if (default_surface.empty()) fail("default_surface must not be empty");
  if (default_shoulder.empty()) fail("default_shoulder must not be empty");
  if (origin && (!(std::abs(origin->lat) <= 90) || !(std::abs(origin->lon) <= 180) || !std::isfinite(origin->alt))) {
    fail("origin must have lat in [-90, 90], lon in [-180, 180] and a finite alt");
  }
}

std::vector<std::pair<std::string, Appearance>> standardSurfaces() {
  auto a = [](double r, double g, double b, double s) { return Appearance{Vec3(r, g, b), Vec3(s, s, s)}; };
  return {{"concrete", a(178, 176, 168, 10)}, {"asphalt", a(88, 90, 96, 10)}, {"brick", a(150, 84, 62, 14)},
          {"gravel", a(140, 132, 118, 18)},   {"grass", a(72, 122, 52, 16)},   {"dirt", a(122, 96, 66, 16)}};
}

namespace {

// A feature as read, before projection: its lon/lat geometry and its properties.
struct RawFeature {
  std::string pointer;  // "/features/k"
  enum class Kind { Road, Point, Polygon, Landmark } kind = Kind::Road;  // Point, Polygon: intersections
  std::vector<LatLon> coordinates;  // the point, or the outer ring without its closing point
  std::vector<std::vector<LatLon>> lines;  // a road's centre line: one (LineString) or more (MultiLineString)
  bool id_from_name = false;  // the id is the feature's "id" member or its "name" property, not properties.id
  std::optional<std::string> id, kind_name, from, to, surface, left, right;
  std::optional<double> width, cost_factor;
  std::optional<bool> oneway;
  std::optional<int> layer;
  std::optional<RoadStructure> structure;
  std::optional<LatLon> center;
  std::optional<LandmarkKind> landmark;     // a landmark's kind (properties.landmark)
  std::optional<double> radius, height;     // a landmark's size
  std::optional<std::string> road;          // the road a landmark stands beside
  Properties extra;  // the members mapnav does not interpret for this kind of feature, kept as they are
};

// The members of a feature's properties that mapnav interprets: for roads, intersections and landmarks.
// A kept property named like one of them (an OSM way's `surface` tag) is written inside the member
// kShadowed instead, and read back from there.
const std::set<std::string, std::less<>> kRoadMembers{"id",    "from",   "to",          "width", "surface",   "left",
                                                      "right", "oneway", "cost_factor", "layer", "structure", "mapnav_kept"};
const std::set<std::string, std::less<>> kIntersectionMembers{"id", "kind", "center", "mapnav_kept"};
const std::set<std::string, std::less<>> kLandmarkMembers{"landmark", "id", "radius", "height", "road", "mapnav_kept"};
constexpr const char* kShadowed = "mapnav_kept";

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

// The kind a node's roads suggest: by how many meet and at what angles.
IntersectionKind inferKind(std::vector<double> headings) {
  const std::size_t n = headings.size();
  if (n <= 1) return IntersectionKind::End;
  if (n >= 5) return IntersectionKind::Plaza;
  if (n == 4) return IntersectionKind::Cross;
  std::sort(headings.begin(), headings.end());
  double smallest = 2 * kPi;
  for (std::size_t i = 0; i < n; ++i) {
    const double next = i + 1 < n ? headings[i + 1] : headings[0] + 2 * kPi;
    smallest = std::min(smallest, next - headings[i]);
  }
  if (n == 2) return smallest < degToRad(150) ? IntersectionKind::L : IntersectionKind::Other;
  return smallest < degToRad(75) ? IntersectionKind::Y : IntersectionKind::T;
}

std::string freshId(const std::string& prefix, std::size_t& counter, const std::set<std::string>& taken) {
  std::string id;
  do {
    id = prefix + std::to_string(++counter);
  } while (taken.contains(id));
  return id;
}

// The FeatureCollection's features as read, and what its "mapnav" member says (the map's name and
// surfaces into `map`, the local frame's origin into `file_origin`). Nothing when the document is
// not a FeatureCollection with a "features" array; bad features are left out with their issues.
std::optional<std::vector<RawFeature>> readFeatureCollection(std::string_view text, Issues& issues, MapData& map,
                                                             std::optional<GeoOrigin>& file_origin) {
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

// The local frame's origin: as asked, as the file says, or about the data's centroid.
GeoOrigin chooseOrigin(const GeoJsonImportOptions& options, const std::optional<GeoOrigin>& file_origin,
                       const std::vector<RawFeature>& raws) {
  if (options.origin) return *options.origin;
  if (file_origin) return *file_origin;
  GeoOrigin origin;
  double lat = 0, lon = 0;
  std::size_t n = 0;
  const auto add = [&](const std::vector<LatLon>& points) {
    for (const LatLon& p : points) {
      lat += p.lat;
      lon += p.lon;
      ++n;
    }
  };
  for (const RawFeature& raw : raws) {
    add(raw.coordinates);
    for (const auto& line : raw.lines) add(line);
  }
  if (n > 0) origin = GeoOrigin{lat / static_cast<double>(n), lon / static_cast<double>(n), 0.0};
  return origin;
}

// Builds the map from the features, projected into the local frame: intersections first (so that
// roads can attach to them), then roads, then the intersections' kinds. Ids not given are made
// fresh ("J1", "R1", ...), never one a feature names.
class MapBuilder {
 public:
  MapBuilder(const GeoJsonImportOptions& options, const GeoOrigin& origin, const std::vector<RawFeature>& raws,
             GeoJsonImport& result)
      : options_(options), frame_(origin), map_(result.map), result_(result) {
    for (const RawFeature& raw : raws) {
      if (raw.id) taken_.insert(*raw.id);
    }
  }

  void addIntersections(const std::vector<RawFeature>& raws) {
    for (const RawFeature& raw : raws) {
      if (raw.kind != RawFeature::Kind::Point && raw.kind != RawFeature::Kind::Polygon) continue;
      Intersection x;
      x.id = raw.id ? *raw.id : freshId("J", next_node_, taken_);
      if (raw.kind == RawFeature::Kind::Point) {
        x.position = frame_.toLocal(raw.coordinates[0]);
      } else {
        x.shape = project(raw.coordinates);
        x.position = raw.center ? frame_.toLocal(*raw.center) : centroid(*x.shape);
      }
      x.properties = raw.extra;
      map_.intersections.push_back(std::move(x));
      result_.intersection_features.push_back(raw.pointer);
      kind_names_.push_back(raw.kind_name);
    }
  }

  // Roads, attaching each end to an intersection: as named, or the one at the end, or one made
  // where road ends meet. A centre line without `from` and `to` is cut at each interior vertex
  // within the snap tolerance of another line's vertex (streets drawn as plain centre lines meet
  // there, not at their ends); each piece, and each part of a MultiLineString, is a road: the
  // feature's id, suffixed -1, -2, ... when it gives more than one.
  void addRoads(const std::vector<RawFeature>& raws) {
    std::vector<Line> lines;
    for (const RawFeature& raw : raws)
      if (raw.kind == RawFeature::Kind::Road)
        for (const auto& part : raw.lines) {
          std::vector<Vec2> points = project(part);
          const std::size_t before = points.size();
          points.erase(std::unique(points.begin(), points.end(), [](const Vec2& a, const Vec2& b) { return (a - b).norm() < 1e-6; }),
                       points.end());
          repeated_ += before - points.size();
          lines.push_back({&raw, std::move(points), {}});
        }
    cutAtSharedVertices(lines);
    std::size_t defaults_width = 0, defaults_surface = 0, named = 0, multi = 0, cut_lines = 0;
    for (const RawFeature& raw : raws) {
      if (raw.kind != RawFeature::Kind::Road) continue;
      std::vector<std::vector<Vec2>> pieces = piecesOf(raw, lines, cut_lines);
      multi += raw.lines.size() > 1;
      named += raw.id_from_name;
      const std::string base = raw.id ? *raw.id : freshId("R", next_road_, taken_);
      for (std::size_t k = 0; k < pieces.size(); ++k) {
        Road road;
        road.id = uniqueRoadId(pieces.size() == 1 ? base : base + "-" + std::to_string(k + 1));
        std::vector<Vec2>& line = pieces[k];
        attachEnd(line.front(), raw.from, road.from);
        attachEnd(line.back(), raw.to, road.to);
        road.centerline = Polyline2(std::move(line));
        road.width = raw.width.value_or(options_.default_width_m);
        road.surface = raw.surface.value_or(options_.default_surface);
        road.left = raw.left.value_or(options_.default_shoulder);
        road.right = raw.right.value_or(options_.default_shoulder);
        defaults_width += !raw.width;
        defaults_surface += !raw.surface;
        road.oneway = raw.oneway.value_or(false);
        road.cost_factor = raw.cost_factor.value_or(1.0);
        road.layer = raw.layer.value_or(0);
        road.structure = raw.structure.value_or(RoadStructure::None);
        road.properties = raw.extra;
        map_.roads.push_back(std::move(road));
        result_.road_features.push_back(raw.pointer);
      }
    }
    note(defaults_width, "roads without a width: " + strprintf("%g", options_.default_width_m) + " m (the default width)");
    note(defaults_surface, "roads without a surface: " + options_.default_surface + ", shoulders " +
                               options_.default_shoulder + " unless given (the defaults)");
    note(named, "road features named by their \"id\" member or \"name\" property (no properties.id)");
    note(multi, "MultiLineString features: a road per part");
    note(cut_lines, "centre lines cut where an interior vertex meets another line's vertex (within " +
                        strprintf("%g", options_.snap_tolerance_m) + " m)");
    note(repeated_, "repeated points of centre lines dropped");
    note(made_nodes_, "intersections made where road ends meet (no Point or Polygon feature there)");
  }

  // Landmarks: Point features with a `landmark` property; the kind's size where the feature gives
  // none, ids made fresh ("L1", "L2", ...) where it gives none.
  void addLandmarks(const std::vector<RawFeature>& raws) {
    std::size_t default_size = 0;
    for (const RawFeature& raw : raws) {
      if (raw.kind != RawFeature::Kind::Landmark) continue;
      Landmark l;
      l.id = raw.id ? *raw.id : freshId("L", next_landmark_, taken_);
      l.kind = *raw.landmark;
      l.position = frame_.toLocal(raw.coordinates[0]);
      const LandmarkSize size = defaultLandmarkSize(l.kind);
      l.radius = raw.radius.value_or(size.radius_m);
      l.height = raw.height.value_or(size.height_m);
      default_size += !raw.radius || !raw.height;
      l.road = raw.road.value_or("");
      l.properties = raw.extra;
      map_.landmarks.push_back(std::move(l));
      result_.landmark_features.push_back(raw.pointer);
    }
    note(default_size, "landmarks without a radius or a height: their kind's size");
  }

  // Kinds: as given, or inferred from the roads that meet. An unknown kind name is an error.
  void assignKinds(Issues& issues) {
    for (std::size_t i = 0; i < map_.intersections.size(); ++i) {
      Intersection& x = map_.intersections[i];
      if (kind_names_[i]) {
        const auto kind = intersectionKindFromString(*kind_names_[i]);
        if (!kind) {
          addIssue(issues, Severity::Error, "schema.enum", result_.intersection_features[i] + "/properties/kind",
                   "unknown intersection kind \"" + *kind_names_[i] + "\"");
          continue;
        }
        x.kind = *kind;
        continue;
      }
      std::vector<double> headings;
      for (const Road& r : map_.roads) {
        const double len = r.centerline.length();
        if (r.from == x.id) headings.push_back(r.centerline.headingAt(0));
        if (r.to == x.id) headings.push_back(normalizeAngle(r.centerline.headingAt(len) + kPi));
      }
      x.kind = inferKind(headings);
    }
  }

 private:
  std::vector<Vec2> project(const std::vector<LatLon>& points) const {
    std::vector<Vec2> out;
    for (const LatLon& p : points) out.push_back(frame_.toLocal(p));
    return out;
  }

  // One line of a road feature (a MultiLineString gives several), projected, and where it is cut.
  struct Line {
    const RawFeature* raw;
    std::vector<Vec2> points;
    std::vector<bool> cut;  // cut[k]: end a piece at vertex k (interior vertices only)
  };

  // The pieces of a road feature's lines, cut where marked; `cut_lines` counts the lines cut.
  static std::vector<std::vector<Vec2>> piecesOf(const RawFeature& raw, const std::vector<Line>& lines, std::size_t& cut_lines) {
    std::vector<std::vector<Vec2>> pieces;
    for (const Line& l : lines) {
      if (l.raw != &raw) continue;
      std::vector<Vec2> piece{l.points.front()};
      for (std::size_t k = 1; k < l.points.size(); ++k) {
        piece.push_back(l.points[k]);
        if (l.cut[k] && k + 1 < l.points.size()) {
          pieces.push_back(std::move(piece));
          piece = {l.points[k]};
        }
      }
      pieces.push_back(std::move(piece));
      cut_lines += std::count(l.cut.begin(), l.cut.end(), true) > 0;
    }
    return pieces;
  }

  // Marks each interior vertex of a line without `from` / `to` that lies within the snap tolerance
  // of a vertex of another line.
  void cutAtSharedVertices(std::vector<Line>& lines) const {
    const double tol2 = options_.snap_tolerance_m * options_.snap_tolerance_m;
    for (Line& l : lines) l.cut.assign(l.points.size(), false);
    const auto cuttable = [](const Line& l, std::size_t k) {
      return !l.raw->from && !l.raw->to && k > 0 && k + 1 < l.points.size();
    };
    for (std::size_t i = 0; i < lines.size(); ++i)
      for (std::size_t j = i + 1; j < lines.size(); ++j)
        for (std::size_t a = 0; a < lines[i].points.size(); ++a)
          for (std::size_t b = 0; b < lines[j].points.size(); ++b) {
            if ((lines[i].points[a] - lines[j].points[b]).squaredNorm() > tol2) continue;
            if (cuttable(lines[i], a)) lines[i].cut[a] = true;
            if (cuttable(lines[j], b)) lines[j].cut[b] = true;
          }
    // No piece shorter than the tolerance: its ends would snap onto one node.
    for (Line& l : lines) {
      Vec2 last = l.points.front();
      for (std::size_t k = 1; k + 1 < l.points.size(); ++k) {
        if (!l.cut[k]) continue;
        if ((l.points[k] - last).squaredNorm() <= tol2 || (l.points[k] - l.points.back()).squaredNorm() <= tol2) l.cut[k] = false;
        else last = l.points[k];
      }
    }
  }

  // "12 roads without a width: ..." among the assumptions, when n > 0.
  void note(std::size_t n, const std::string& text) {
    if (n > 0) result_.assumptions.push_back(std::to_string(n) + " " + text);
  }

  // `id`, or `id` suffixed ~2, ~3, ... when a road has it already (two features of one name).
  std::string uniqueRoadId(const std::string& id) {
    std::string out = id;
    for (int n = 2; !road_ids_.insert(out).second; ++n) out = id + "~" + std::to_string(n);
    return out;
  }

  // The intersection nearest to `p` within the snap tolerance (0 inside an intersection's shape).
  std::optional<std::size_t> nodeAt(const Vec2& p) const {
    std::optional<std::size_t> best;
    double best_d = options_.snap_tolerance_m;
    for (std::size_t i = 0; i < map_.intersections.size(); ++i) {
      const Intersection& x = map_.intersections[i];
      const double d = (x.shape && contains(*x.shape, p)) ? 0.0 : (x.position - p).norm();
      if (d <= best_d) {
        best_d = d;
        best = i;
      }
    }
    return best;
  }

  // Sets `target` to the intersection road end `p` attaches to: `named`, or the node at `p` (made
  // when there is none), onto whose position `p` is snapped unless it lies inside the node's shape.
  void attachEnd(Vec2& p, const std::optional<std::string>& named, std::string& target) {
    if (named) {
      target = *named;
      return;
    }
    std::optional<std::size_t> node = nodeAt(p);
    if (!node) {
      Intersection x;
      x.id = freshId("J", next_node_, taken_);
      x.position = p;
      map_.intersections.push_back(std::move(x));
      result_.intersection_features.emplace_back();
      kind_names_.emplace_back();
      ++made_nodes_;
      node = map_.intersections.size() - 1;
    }
    const Intersection& x = map_.intersections[*node];
    if (!x.shape || !contains(*x.shape, p)) p = x.position;  // snap the end onto the node
    target = x.id;
  }

  const GeoJsonImportOptions& options_;
  const LocalFrame frame_;
  MapData& map_;
  GeoJsonImport& result_;
  std::set<std::string> taken_;
  std::size_t next_road_ = 0, next_node_ = 0, next_landmark_ = 0;
  std::vector<std::optional<std::string>> kind_names_;  // as given, per intersection
  std::set<std::string> road_ids_;                      // the roads' ids so far
  std::size_t made_nodes_ = 0;                          // intersections made at road ends
  std::size_t repeated_ = 0;                            // repeated centre-line points dropped
};

}  // namespace

std::optional<GeoJsonImport> importGeoJson(std::string_view text, Issues& issues, const GeoJsonImportOptions& options) {
  options.validate();
  const std::size_t errors_before = countSeverity(issues, Severity::Error);
  GeoJsonImport result;
  MapData& map = result.map;
  map.name = "imported from GeoJSON";
  map.surfaces = standardSurfaces();
  std::optional<GeoOrigin> file_origin;
  const std::optional<std::vector<RawFeature>> raws = readFeatureCollection(text, issues, map, file_origin);
  if (!raws || countSeverity(issues, Severity::Error) != errors_before) return std::nullopt;

  map.origin = chooseOrigin(options, file_origin, *raws);
  MapBuilder builder(options, *map.origin, *raws, result);
  builder.addIntersections(*raws);
  builder.addRoads(*raws);
  builder.addLandmarks(*raws);
  builder.assignKinds(issues);
  if (countSeverity(issues, Severity::Error) != errors_before) return std::nullopt;
  return result;
}

std::string GeoJsonImport::toFeaturePointer(const std::string& map_pointer) const {
  // "/roads/3/centerline/2" → ["roads", "3", "centerline", "2"]
  std::vector<std::string> parts;
  std::stringstream in(map_pointer.size() > 1 ? map_pointer.substr(1) : "");
  for (std::string part; std::getline(in, part, '/');) parts.push_back(part);
  if (parts.size() < 2) return map_pointer;
  const std::vector<std::string>* features = parts[0] == "roads"           ? &road_features
                                             : parts[0] == "intersections" ? &intersection_features
                                             : parts[0] == "landmarks"     ? &landmark_features
                                                                           : nullptr;
  if (features == nullptr) return map_pointer;
  std::size_t index = 0;
  try {
    index = std::stoul(parts[1]);
  } catch (...) {
    return map_pointer;
  }
  if (index >= features->size() || (*features)[index].empty()) return map_pointer;
  std::string out = (*features)[index];
  if (parts.size() == 2) return out;
  const std::string& member = parts[2];
  if (member == "centerline") {
    out += "/geometry/coordinates";
  } else if (member == "shape") {
    out += "/geometry/coordinates/0";
  } else if (member == "position") {
    out += "/geometry/coordinates";
  } else if (parts[0] == "landmarks" && member == "kind") {
    out += "/properties/landmark";
  } else {
    out += "/properties/" + member;
  }
  for (std::size_t i = 3; i < parts.size(); ++i) out += "/" + parts[i];
  return out;
}

namespace {

// The element's kept properties after the members mapnav writes; those named like one of them
// (which a re-import would read as that member) inside kShadowed.
void addKept(Json& out, const Properties& kept, const std::set<std::string, std::less<>>& interpreted) {
  Json shadowed = Json::object();
  for (const auto& [key, value] : kept) (interpreted.contains(key) ? shadowed[key] : out[key]) = propertyToJson(value);
  if (!shadowed.empty()) out[kShadowed] = std::move(shadowed);
}

}  // namespace

std::string exportGeoJson(const MapData& map, const std::optional<GeoOrigin>& origin_override) {
  const std::optional<GeoOrigin> origin = origin_override ? origin_override : map.origin;
  if (!origin) {
    throw InvalidInput("map \"" + map.name + "\" has no geodetic origin; give one (--origin LAT,LON) to export GeoJSON");
  }
  const LocalFrame frame(*origin);
  auto position = [&](const Vec2& p) {
    const LatLon g = frame.toGeodetic(p);
    // 9 decimals: 0.1 mm, so that export → import is exact to well under a millimetre.
    return Json::array({std::round(g.lon * 1e9) / 1e9, std::round(g.lat * 1e9) / 1e9});
  };
  auto positions = [&](const std::vector<Vec2>& points) {
    Json out = Json::array();
    for (const Vec2& p : points) out.push_back(position(p));
    return out;
  };
  Json features = Json::array();
  for (const Intersection& x : map.intersections) {
    Json properties = {{"id", x.id}, {"kind", toString(x.kind)}};
    Json geometry;
    if (x.shape) {
      Json ring = positions(*x.shape);
      ring.push_back(ring.front());
      geometry = {{"type", "Polygon"}, {"coordinates", Json::array({ring})}};
      properties["center"] = position(x.position);
    } else {
      geometry = {{"type", "Point"}, {"coordinates", position(x.position)}};
    }
    addKept(properties, x.properties, kIntersectionMembers);
    features.push_back({{"type", "Feature"}, {"properties", properties}, {"geometry", geometry}});
  }
  for (const Road& r : map.roads) {
    Json properties = {{"id", r.id}, {"from", r.from}, {"to", r.to}, {"width", r.width},
                       {"surface", r.surface}, {"left", r.left}, {"right", r.right}};
    if (r.oneway) properties["oneway"] = true;
    if (r.cost_factor != 1.0) properties["cost_factor"] = r.cost_factor;
    if (r.layer != 0) properties["layer"] = r.layer;
    if (r.structure != RoadStructure::None) properties["structure"] = toString(r.structure);
    addKept(properties, r.properties, kRoadMembers);
    Json geometry = {{"type", "LineString"}, {"coordinates", positions(r.centerline.points())}};
    features.push_back({{"type", "Feature"}, {"properties", properties}, {"geometry", geometry}});
  }
  for (const Landmark& l : map.landmarks) {
    Json properties = {{"landmark", toString(l.kind)}, {"id", l.id}, {"radius", l.radius}, {"height", l.height}};
    if (!l.road.empty()) properties["road"] = l.road;
    addKept(properties, l.properties, kLandmarkMembers);
    Json geometry = {{"type", "Point"}, {"coordinates", position(l.position)}};
    features.push_back({{"type", "Feature"}, {"properties", properties}, {"geometry", geometry}});
  }
  Json meta = {{"format", kMapFormat}, {"name", map.name}, {"origin", originToJson(*origin)},
               {"surfaces", surfacesToJson(map.surfaces)}};
  Json doc = {{"type", "FeatureCollection"}, {"mapnav", meta}, {"features", features}};
  return dumpJson(doc);
}

}  // namespace mapnav
