#pragma once
// The papers' two maps in one model (Wallace 1985, 2.1.2): the topological map (intersections are
// nodes, roads are edges) and the geometric map (their shapes). `MapData` is the map as authored,
// plain data that may be invalid; `Map` is a validated map with lookups and a spatial index.
#include <cstddef>
#include <iosfwd>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mapnav/core/issue.h"
#include "mapnav/geometry/polyline2.h"
#include "mapnav/geometry/types.h"

namespace mapnav {

enum class IntersectionKind { Cross, T, Y, L, End, Plaza, Other };
std::string_view toString(IntersectionKind kind);
std::optional<IntersectionKind> intersectionKindFromString(std::string_view text);
/// Every kind, in declaration order (for help texts and enumerations).
const std::vector<IntersectionKind>& allIntersectionKinds();

/// What carries a road over or under the others (OSM's `bridge`, `tunnel` and `covered` tags): a
/// bridge is drawn with a casing, a tunnel dashed and is not in a view from outside it.
enum class RoadStructure { None, Bridge, Tunnel };
/// "none", "bridge", "tunnel".
std::string_view toString(RoadStructure structure);
std::optional<RoadStructure> roadStructureFromString(std::string_view text);

/// How a surface looks to the camera: mean colour and its standard deviation, 0–255 RGB.
struct Appearance {
  Vec3 rgb = Vec3::Zero();
  Vec3 spread = Vec3::Zero();
  bool operator==(const Appearance&) const = default;
};

/// The geodetic point at the local frame's origin (WGS84, degrees, metres).
struct GeoOrigin {
  double lat = 0, lon = 0, alt = 0;
  bool operator==(const GeoOrigin&) const = default;
};

/// One property's value: a string, or any other JSON value (a number, true, an array, a nested
/// object) kept as its compact JSON text, so that what mapnav does not interpret survives a round
/// trip through the map and GeoJSON without this header knowing JSON.
struct PropertyValue {
  std::string text;      ///< the string itself, or the JSON text of a value that is not a string
  bool is_json = false;  ///< `text` is JSON text

  PropertyValue() = default;
  PropertyValue(std::string value) : text(std::move(value)) {}  // NOLINT: a string converts implicitly
  PropertyValue(const char* value) : text(value) {}             // NOLINT
  /// A value that is not a string, as JSON text ("3", "[1,2]", "{\"a\":null}").
  static PropertyValue json(std::string json_text) {
    PropertyValue v(std::move(json_text));
    v.is_json = true;
    return v;
  }
  bool operator==(const PropertyValue&) const = default;
};
/// For test failures: the string quoted, JSON text as it is.
std::ostream& operator<<(std::ostream& out, const PropertyValue& value);

/// Free-form properties kept with an element, for people and other tools (the OSM ids and tags of
/// an imported map: `osm_node`, `osm_way`, `highway`, `name`; anything a GeoJSON feature carries
/// that mapnav does not interpret). mapnav itself never reads them; it writes them back.
using Properties = std::map<std::string, PropertyValue>;

struct Intersection {
  std::string id;
  IntersectionKind kind = IntersectionKind::Other;
  Vec2 position = Vec2::Zero();    ///< where the centre lines meet
  std::optional<Polygon2> shape;   ///< the paved outline as authored; derived by Map when absent
  Properties properties = {};  ///< see Properties
  bool operator==(const Intersection&) const = default;
};

struct Road {
  std::string id;
  std::string from, to;            ///< intersection ids; the centre line runs from → to
  Polyline2 centerline;
  double width = 2.0;              ///< paved width, metres
  std::string surface;             ///< key of MapData::surfaces
  std::string left, right;         ///< shoulder surfaces seen walking from → to
  bool oneway = false;             ///< drivable only from → to
  double cost_factor = 1.0;        ///< multiplies the length in route costs
  /// The level the road is on (OSM `layer`; 0 the ground): roads on different layers may cross
  /// without an intersection (a bridge over a path), roads on the same layer may not.
  int layer = 0;
  RoadStructure structure = RoadStructure::None;  ///< see RoadStructure
  /// How well the road's place is known, 1-sigma per axis, m (>= 0); none: the map's
  /// (MapData::position_sigma_m). See positionSigma().
  std::optional<double> position_sigma_m;
  Properties properties = {};  ///< see Properties
  bool operator==(const Road&) const = default;
};

/// What a landmark is: something beside a road that a camera sees at a known place and
/// that fixes the position along the road where no intersection is in view. Poles, trees, bollards
/// and benches stand up from the ground; a manhole cover lies flat in the paving.
enum class LandmarkKind { Pole, Tree, Bench, Bollard, Manhole };
/// "pole", "tree", "bench", "bollard", "manhole".
std::string_view toString(LandmarkKind kind);
std::optional<LandmarkKind> landmarkKindFromString(std::string_view text);
/// Every kind, in declaration order (for help texts and enumerations).
const std::vector<LandmarkKind>& allLandmarkKinds();

/// A landmark's size when the map does not give one, m: a street lamp's post (radius 0.10, 5 m
/// tall), a tree's trunk (0.15, crown top at 6 m), a bench (0.8 along its seat, 0.8 tall), a
/// bollard (0.08, 0.9 tall), a manhole cover (0.30, flat).
struct LandmarkSize {
  double radius_m = 0;  ///< of the trunk, post or cover; half the length of a bench
  double height_m = 0;  ///< of its top above the ground; 0 for a flat mark
};
LandmarkSize defaultLandmarkSize(LandmarkKind kind);
/// A bench is this deep across its road (its radius is half its length along the road), m.
inline constexpr double kBenchDepthM = 0.5;
/// Does the kind stand up from the ground (everything but a manhole cover)?
bool isUpright(LandmarkKind kind);

/// A point feature beside (or, for a manhole, in) a road. Frames: world, metres.
struct Landmark {
  std::string id;                   ///< unique among intersections, roads and landmarks
  LandmarkKind kind = LandmarkKind::Pole;
  Vec2 position = Vec2::Zero();     ///< where it meets the ground: the trunk's, post's or cover's centre
  double radius = 0.1;              ///< m; see LandmarkSize
  double height = 5.0;              ///< m; see LandmarkSize
  /// The road it stands beside (an id); empty: the nearest road, found by Map::roadBeside.
  std::string road;
  Properties properties = {};  ///< see Properties
  bool operator==(const Landmark&) const = default;
};

/// How far a landmark reaches from its position across its road: its radius, or half a bench's depth.
double landmarkHalfWidth(const Landmark& landmark);

/// The map as authored (the file's content). May be invalid: see validateMap().
struct MapData {
  std::string name;
  std::string schema;              ///< the file's "$schema", written back as it was ("" = none)
  std::optional<GeoOrigin> origin;
  std::vector<std::pair<std::string, Appearance>> surfaces;  ///< in the file's order
  std::vector<Intersection> intersections;
  std::vector<Road> roads;
  std::vector<Landmark> landmarks;  ///< optional in the file; none by default
  /// How well the map's roads are placed in the world, 1-sigma per axis of a centre line's position,
  /// m (>= 0; a road may say otherwise). 0, the default of a mapnav map: exact (the simulator's
  /// maps, a survey to centimetres). The importers write what their sources give
  /// (kGeoJsonPositionSigmaM, kOsmPositionSigmaM). The pose filter takes the map's error as slowly
  /// varying along the road (FilterOptions::map_correlation_m): the lines fix the pose relative to
  /// the map, and the pose in the world is uncertain by this on top.
  double position_sigma_m = 0;
  bool operator==(const MapData&) const = default;
};

/// The default position_sigma_m of a map imported from GeoJSON (`mapnav map import-geojson`): 0.5 m,
/// centre lines drawn over aerial imagery in QGIS or geojson.io, whose registration is 0.3-1 m.
inline constexpr double kGeoJsonPositionSigmaM = 0.5;
/// ... and from OpenStreetMap (`mapnav import-osm`): 1 m, OSM's centre lines, the carriageway's or
/// the path's middle to within a lane (docs/real-drive.md measures 0.1-0.8 m on Ostring).
inline constexpr double kOsmPositionSigmaM = 1.0;

/// The largest position_sigma_m a map or road may state, m (a map that far off is no map).
inline constexpr double kMaxPositionSigmaM = 100.0;

/// `road`'s position_sigma_m, else `map`'s.
inline double positionSigma(const MapData& map, const Road& road) {
  return road.position_sigma_m.value_or(map.position_sigma_m);
}

/// A validated map. Invariant: validateMap(data()) reports no error. Lookups are O(1); spatial
/// queries use an R-tree, so their cost grows with what is found, not with the map.
struct ValidationOptions;

class Map {
 public:
  /// Validates `data` and throws ValidationError (every issue, naming `source`) when it has errors.
  explicit Map(MapData data, std::string source = "<map>");
  Map(MapData data, std::string source, const ValidationOptions& options);
  ~Map();
  Map(Map&&) noexcept;
  Map& operator=(Map&&) noexcept;

  const MapData& data() const;
  /// The warnings validation found (a valid map has no errors, but may have warnings).
  const Issues& warnings() const;
  const std::string& name() const { return data().name; }
  const std::vector<Intersection>& intersections() const { return data().intersections; }
  const std::vector<Road>& roads() const { return data().roads; }
  const std::vector<Landmark>& landmarks() const { return data().landmarks; }

  /// nullptr when there is no such id.
  const Intersection* findIntersection(std::string_view id) const;
  const Road* findRoad(std::string_view id) const;
  const Appearance* findSurface(std::string_view name) const;
  /// Throw NotFound naming the id.
  const Intersection& intersection(std::string_view id) const;
  const Road& road(std::string_view id) const;

  /// One end of a road at an intersection.
  struct RoadEnd {
    const Road* road = nullptr;
    bool at_from = true;     ///< the road's `from` end (else its `to` end) is at the intersection
    double heading_out = 0;  ///< heading leaving the intersection along the road, radians
  };
  /// The road ends at an intersection, sorted by heading_out (counter-clockwise from +x). A loop
  /// road appears twice.
  std::vector<RoadEnd> roadsAt(std::string_view intersection_id) const;
  /// The intersections one road away, without repeats, in id order.
  std::vector<const Intersection*> neighbours(std::string_view intersection_id) const;

  /// The road's edges, offset ±width/2 from the centre line (left seen walking from → to).
  const Polyline2& leftEdge(const Road& road) const;
  const Polyline2& rightEdge(const Road& road) const;
  /// The paved area: the left edge then the right edge reversed.
  Polygon2 roadPolygon(const Road& road) const;
  /// The authored shape, or one derived from the meeting roads' edges (the convex hull of the
  /// edge points where they enter the intersection, half the widest road deep), counter-clockwise.
  const Polygon2& intersectionShape(const Intersection& intersection) const;

  /// Roads whose paved area comes within `radius` metres of p, nearest first (ties by id).
  std::vector<const Road*> roadsNear(const Vec2& p, double radius) const;
  /// Roads whose paved area meets the polygon, in id order.
  std::vector<const Road*> roadsMeeting(const Polygon2& polygon) const;
  /// Intersections whose shape meets the polygon, in id order.
  std::vector<const Intersection*> intersectionsMeeting(const Polygon2& polygon) const;
  /// Landmarks whose position lies inside the polygon, in the map's order.
  std::vector<const Landmark*> landmarksIn(const Polygon2& polygon) const;
  /// The road a landmark stands beside: the one it names, else the road whose paved area is
  /// nearest (nullptr when the map has no road).
  const Road* roadBeside(const Landmark& landmark) const;

  /// Everything paved, with road widths and intersection shapes.
  Box2 bounds() const;
  /// The connected pieces of the network: each a list of intersection indices, ascending; the
  /// piece holding intersections[0] first.
  const std::vector<std::vector<std::size_t>>& components() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mapnav
