#include "mapnav/map/geojson.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "geojson_internal.h"
#include "map_json_internal.h"
#include "mapnav/core/error.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/geometry/polygon.h"
#include "mapnav/map/geodesy.h"
#include "mapnav/map/map_io.h"

namespace mapnav {

const OptionTable<GeoJsonImportOptions>& geoJsonImportOptionTable() {
  using O = GeoJsonImportOptions;
  static const OptionTable<O> table =
      OptionTable<O>("GeoJsonImportOptions")
          .field("snap_tolerance_m", &O::snap_tolerance_m, atLeast(0),
                 "road ends and vertices closer than this share a node or cut a line, m")
          .field("default_width_m", &O::default_width_m, above(0), "the width of a LineString without one, m")
          .field("default_surface", &O::default_surface, "the surface of a LineString without one")
          .field("default_shoulder", &O::default_shoulder, "the shoulder of a LineString without one")
          .field("position_sigma_m", &O::position_sigma_m, inRange(0, kMaxPositionSigmaM),
                 "how well the roads are placed, 1-sigma per axis, m, when the file's mapnav member does not say")
          .check("default_surface", [](const O& o) { return !o.default_surface.empty(); }, "non-empty")
          .check("default_shoulder", [](const O& o) { return !o.default_shoulder.empty(); }, "non-empty");
  return table;
}

void GeoJsonImportOptions::validate() const {
  geoJsonImportOptionTable().validate(*this);
  // An origin that may be absent: no value a table holds.
  if (origin && (!(std::abs(origin->lat) <= 90) || !(std::abs(origin->lon) <= 180) || !std::isfinite(origin->alt)))
    throw InvalidInput("GeoJsonImportOptions::origin must have lat in [-90, 90], lon in [-180, 180] and a finite alt");
}

std::vector<std::pair<std::string, Appearance>> standardSurfaces() {
  auto a = [](double r, double g, double b, double s) { return Appearance{Vec3(r, g, b), Vec3(s, s, s)}; };
  return {{"concrete", a(178, 176, 168, 10)}, {"asphalt", a(88, 90, 96, 10)}, {"brick", a(150, 84, 62, 14)},
          {"gravel", a(140, 132, 118, 18)},   {"grass", a(72, 122, 52, 16)},   {"dirt", a(122, 96, 66, 16)}};
}

namespace {

using geojson::kIntersectionMembers;
using geojson::kLandmarkMembers;
using geojson::kRoadMembers;
using geojson::kShadowed;
using geojson::RawFeature;
using geojson::readFeatureCollection;

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
        road.position_sigma_m = raw.position_sigma_m;
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
  std::optional<double> file_sigma;
  const std::optional<std::vector<RawFeature>> raws = readFeatureCollection(text, issues, map, file_origin, file_sigma);
  if (!raws || countSeverity(issues, Severity::Error) != errors_before) return std::nullopt;
  map.position_sigma_m = file_sigma.value_or(options.position_sigma_m);
  if (!file_sigma) {
    result.assumptions.push_back(strprintf("the roads placed to %g m (1 sigma; the file's mapnav member does not say)",
                                           options.position_sigma_m));
  }

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
    throw InvalidInput("map \"" + map.name + "\" has no geodetic origin: give one to export GeoJSON (latitude, longitude)");
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
    if (r.position_sigma_m) properties["position_sigma_m"] = *r.position_sigma_m;
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
               {"position_sigma_m", map.position_sigma_m}, {"surfaces", surfacesToJson(map.surfaces)}};
  Json doc = {{"type", "FeatureCollection"}, {"mapnav", meta}, {"features", features}};
  return dumpJson(doc);
}

}  // namespace mapnav
