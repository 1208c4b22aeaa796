#include "mapnav/map/map.h"

#include <algorithm>
#include <array>
#include <ostream>
#include <unordered_map>

#include "mapnav/core/error.h"
#include "mapnav/geometry/polygon.h"
#include "mapnav/map/validation.h"
#include "spatial_internal.h"

namespace mapnav {

namespace bgi = boost::geometry::index;
using spatial::BBox;
using spatial::toBBox;

namespace {

constexpr std::array<std::pair<IntersectionKind, std::string_view>, 7> kKindNames{{
    {IntersectionKind::Cross, "cross"},
    {IntersectionKind::T, "T"},
    {IntersectionKind::Y, "Y"},
    {IntersectionKind::L, "L"},
    {IntersectionKind::End, "end"},
    {IntersectionKind::Plaza, "plaza"},
    {IntersectionKind::Other, "other"},
}};

constexpr std::array<std::pair<RoadStructure, std::string_view>, 3> kStructureNames{{
    {RoadStructure::None, "none"},
    {RoadStructure::Bridge, "bridge"},
    {RoadStructure::Tunnel, "tunnel"},
}};

constexpr std::array<std::pair<LandmarkKind, std::string_view>, 5> kLandmarkNames{{
    {LandmarkKind::Pole, "pole"},
    {LandmarkKind::Tree, "tree"},
    {LandmarkKind::Bench, "bench"},
    {LandmarkKind::Bollard, "bollard"},
    {LandmarkKind::Manhole, "manhole"},
}};

// What an R-tree entry stands for: a road segment or an intersection shape.
struct Entry {
  bool is_road;
  std::size_t index;    // road or intersection index
  std::size_t segment;  // road segment
};
using Value = std::pair<BBox, Entry>;
using RTree = bgi::rtree<Value, bgi::rstar<16>>;

Box2 expanded(Box2 b, double margin) {
  b.min().array() -= margin;
  b.max().array() += margin;
  return b;
}

double segmentDistance(const Segment2& s, const Segment2& t) {
  if (segmentsIntersect(s, t)) return 0.0;
  return std::min({s.distanceTo(t.a), s.distanceTo(t.b), t.distanceTo(s.a), t.distanceTo(s.b)});
}

// Does the area within `radius` of polyline segment `s` meet the polygon?
bool segmentNearPolygon(const Segment2& s, double radius, const Polygon2& polygon) {
  if (contains(polygon, s.a) || contains(polygon, s.b)) return true;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Segment2 edge{polygon[i], polygon[(i + 1) % polygon.size()]};
    if (segmentDistance(s, edge) <= radius) return true;
  }
  return false;
}

Box2 polygonBounds(const Polygon2& ring) {
  Box2 box;
  for (const Vec2& p : ring) box.extend(p);
  return box;
}

}  // namespace

std::string_view toString(IntersectionKind kind) {
  for (const auto& [k, name] : kKindNames) {
    if (k == kind) return name;
  }
  return "other";
}

std::optional<IntersectionKind> intersectionKindFromString(std::string_view text) {
  for (const auto& [k, name] : kKindNames) {
    if (name == text) return k;
  }
  return std::nullopt;
}

std::ostream& operator<<(std::ostream& out, const PropertyValue& value) {
  return value.is_json ? out << value.text : out << '"' << value.text << '"';
}

std::string_view toString(RoadStructure structure) {
  for (const auto& [s, name] : kStructureNames) {
    if (s == structure) return name;
  }
  return "none";
}

std::optional<RoadStructure> roadStructureFromString(std::string_view text) {
  for (const auto& [s, name] : kStructureNames) {
    if (name == text) return s;
  }
  return std::nullopt;
}

const std::vector<IntersectionKind>& allIntersectionKinds() {
  static const std::vector<IntersectionKind> kinds = [] {
    std::vector<IntersectionKind> out;
    for (const auto& entry : kKindNames) out.push_back(entry.first);
    return out;
  }();
  return kinds;
}

std::string_view toString(LandmarkKind kind) {
  for (const auto& [k, name] : kLandmarkNames) {
    if (k == kind) return name;
  }
  return "pole";
}

std::optional<LandmarkKind> landmarkKindFromString(std::string_view text) {
  for (const auto& [k, name] : kLandmarkNames) {
    if (name == text) return k;
  }
  return std::nullopt;
}

const std::vector<LandmarkKind>& allLandmarkKinds() {
  static const std::vector<LandmarkKind> kinds = [] {
    std::vector<LandmarkKind> out;
    for (const auto& entry : kLandmarkNames) out.push_back(entry.first);
    return out;
  }();
  return kinds;
}

LandmarkSize defaultLandmarkSize(LandmarkKind kind) {
  switch (kind) {
    case LandmarkKind::Pole: return {0.10, 5.0};
    case LandmarkKind::Tree: return {0.15, 6.0};
    case LandmarkKind::Bench: return {0.80, 0.8};
    case LandmarkKind::Bollard: return {0.08, 0.9};
    case LandmarkKind::Manhole: return {0.30, 0.0};
  }
  return {0.10, 5.0};
}

bool isUpright(LandmarkKind kind) { return kind != LandmarkKind::Manhole; }

double landmarkHalfWidth(const Landmark& landmark) {
  return landmark.kind == LandmarkKind::Bench ? kBenchDepthM / 2 : landmark.radius;
}

struct Map::Impl {
  MapData data;
  Issues warnings;
  std::unordered_map<std::string, std::size_t> road_index, intersection_index, surface_index;
  std::vector<std::vector<RoadEnd>> ends;  // per intersection
  std::vector<Polyline2> left, right;      // per road
  std::vector<Polygon2> shapes;            // per intersection
  std::vector<std::vector<std::size_t>> components;
  RTree tree;
  bgi::rtree<std::pair<spatial::BPoint, std::size_t>, bgi::rstar<16>> landmark_tree;  // position → index
  Box2 bounds;

  std::size_t roadIndex(const Road& road) const {
    return static_cast<std::size_t>(&road - data.roads.data());
  }
  std::size_t intersectionIndex(const Intersection& i) const {
    return static_cast<std::size_t>(&i - data.intersections.data());
  }

  void build();
  Polygon2 deriveShape(std::size_t i) const;
  /// The R-tree entries whose boxes meet `box`.
  std::vector<Value> candidates(const Box2& box) const {
    std::vector<Value> found;
    tree.query(bgi::intersects(toBBox(box)), std::back_inserter(found));
    return found;
  }
};

void Map::Impl::build() {
  for (std::size_t i = 0; i < data.roads.size(); ++i) road_index.emplace(data.roads[i].id, i);
  for (std::size_t i = 0; i < data.intersections.size(); ++i) intersection_index.emplace(data.intersections[i].id, i);
  for (std::size_t i = 0; i < data.surfaces.size(); ++i) surface_index.emplace(data.surfaces[i].first, i);

  ends.resize(data.intersections.size());
  for (const Road& road : data.roads) {
    left.push_back(road.centerline.offset(road.width / 2));
    right.push_back(road.centerline.offset(-road.width / 2));
    const Polyline2& c = road.centerline;
    const double len = c.length();
    ends[intersection_index.at(road.from)].push_back(RoadEnd{&road, true, c.headingAt(0)});
    ends[intersection_index.at(road.to)].push_back(
        RoadEnd{&road, false, normalizeAngle(c.headingAt(len) + kPi)});
  }
  for (auto& list : ends) {
    std::stable_sort(list.begin(), list.end(), [](const RoadEnd& a, const RoadEnd& b) {
      return a.heading_out < b.heading_out;
    });
  }

  for (std::size_t i = 0; i < data.intersections.size(); ++i) {
    const Intersection& x = data.intersections[i];
    shapes.push_back(x.shape ? counterClockwise(*x.shape) : deriveShape(i));
  }

  std::vector<std::pair<std::size_t, std::size_t>> edges;
  for (const Road& road : data.roads) edges.emplace_back(intersection_index.at(road.from), intersection_index.at(road.to));
  const std::vector<std::size_t> label = spatial::componentLabels(data.intersections.size(), edges);
  std::unordered_map<std::size_t, std::size_t> component_of_label;
  for (std::size_t i = 0; i < label.size(); ++i) {
    const auto [it, inserted] = component_of_label.emplace(label[i], components.size());
    if (inserted) components.emplace_back();
    components[it->second].push_back(i);
  }

  // The R-tree, bulk-loaded (packing gives better queries than one-by-one insertion).
  std::vector<Value> values;
  for (std::size_t r = 0; r < data.roads.size(); ++r) {
    const Road& road = data.roads[r];
    for (std::size_t s = 0; s < road.centerline.segmentCount(); ++s) {
      const Box2 box = expanded(road.centerline.segment(s).bounds(), road.width / 2);
      values.emplace_back(toBBox(box), Entry{true, r, s});
      bounds.extend(box);
    }
  }
  for (std::size_t i = 0; i < shapes.size(); ++i) {
    const Box2 box = polygonBounds(shapes[i]);
    values.emplace_back(toBBox(box), Entry{false, i, 0});
    bounds.extend(box);
  }
  tree = RTree(values.begin(), values.end());
  std::vector<std::pair<spatial::BPoint, std::size_t>> landmark_points;
  for (std::size_t i = 0; i < data.landmarks.size(); ++i) {
    landmark_points.emplace_back(spatial::BPoint(data.landmarks[i].position.x(), data.landmarks[i].position.y()), i);
  }
  landmark_tree = decltype(landmark_tree)(landmark_points.begin(), landmark_points.end());
}

Polygon2 Map::Impl::deriveShape(std::size_t i) const {
  const Intersection& x = data.intersections[i];
  const auto& list = ends[i];
  if (list.empty()) {
    const double h = 0.5;
    return {x.position + Vec2(-h, -h), x.position + Vec2(h, -h), x.position + Vec2(h, h), x.position + Vec2(-h, h)};
  }
  double depth = 0;
  for (const RoadEnd& e : list) depth = std::max(depth, e.road->width / 2);
  std::vector<Vec2> points;
  for (const RoadEnd& e : list) {
    const std::size_t r = roadIndex(*e.road);
    const double len = e.road->centerline.length();
    // Arc lengths on the edges: at the intersection end, and `depth` into the road.
    for (double d : {0.0, std::min(depth, len / 2)}) {
      const double s = e.at_from ? d : len - d;
      points.push_back(left[r].pointAt(s));
      points.push_back(right[r].pointAt(s));
    }
  }
  Polygon2 hull = convexHull(points);
  if (hull.size() < 3) {  // all points on a line: fall back to a small square
    const double h = std::max(depth, 0.5);
    return {x.position + Vec2(-h, -h), x.position + Vec2(h, -h), x.position + Vec2(h, h), x.position + Vec2(-h, h)};
  }
  return hull;
}

Map::Map(MapData data, std::string source) : Map(std::move(data), std::move(source), ValidationOptions{}) {}

Map::Map(MapData data, std::string source, const ValidationOptions& options) : impl_(std::make_unique<Impl>()) {
  Issues issues = validateMap(data, options);
  if (hasErrors(issues)) throw ValidationError(std::move(source), std::move(issues));
  impl_->warnings = std::move(issues);
  impl_->data = std::move(data);
  impl_->build();
}

Map::~Map() = default;
Map::Map(Map&&) noexcept = default;
Map& Map::operator=(Map&&) noexcept = default;

const MapData& Map::data() const { return impl_->data; }
const Issues& Map::warnings() const { return impl_->warnings; }

const Intersection* Map::findIntersection(std::string_view id) const {
  const auto it = impl_->intersection_index.find(std::string(id));
  return it == impl_->intersection_index.end() ? nullptr : &impl_->data.intersections[it->second];
}

const Road* Map::findRoad(std::string_view id) const {
  const auto it = impl_->road_index.find(std::string(id));
  return it == impl_->road_index.end() ? nullptr : &impl_->data.roads[it->second];
}

const Appearance* Map::findSurface(std::string_view name) const {
  const auto it = impl_->surface_index.find(std::string(name));
  return it == impl_->surface_index.end() ? nullptr : &impl_->data.surfaces[it->second].second;
}

const Intersection& Map::intersection(std::string_view id) const {
  if (const Intersection* x = findIntersection(id)) return *x;
  throw NotFound("no intersection \"" + std::string(id) + "\" in map \"" + name() + "\"");
}

const Road& Map::road(std::string_view id) const {
  if (const Road* r = findRoad(id)) return *r;
  throw NotFound("no road \"" + std::string(id) + "\" in map \"" + name() + "\"");
}

std::vector<Map::RoadEnd> Map::roadsAt(std::string_view intersection_id) const {
  return impl_->ends[impl_->intersectionIndex(intersection(intersection_id))];
}

std::vector<const Intersection*> Map::neighbours(std::string_view intersection_id) const {
  const Intersection& self = intersection(intersection_id);
  std::vector<const Intersection*> out;
  for (const RoadEnd& e : roadsAt(intersection_id)) {
    const Intersection* other = &intersection(e.at_from ? e.road->to : e.road->from);
    if (other != &self && std::find(out.begin(), out.end(), other) == out.end()) out.push_back(other);
  }
  std::sort(out.begin(), out.end(), [](const Intersection* a, const Intersection* b) { return a->id < b->id; });
  return out;
}

const Polyline2& Map::leftEdge(const Road& road) const { return impl_->left[impl_->roadIndex(road)]; }
const Polyline2& Map::rightEdge(const Road& road) const { return impl_->right[impl_->roadIndex(road)]; }

Polygon2 Map::roadPolygon(const Road& road) const {
  Polygon2 ring = leftEdge(road).points();
  const auto& r = rightEdge(road).points();
  ring.insert(ring.end(), r.rbegin(), r.rend());
  return ring;
}

const Polygon2& Map::intersectionShape(const Intersection& x) const {
  return impl_->shapes[impl_->intersectionIndex(x)];
}

std::vector<const Road*> Map::roadsNear(const Vec2& p, double radius) const {
  const auto found = impl_->candidates(Box2(p - Vec2::Constant(radius), p + Vec2::Constant(radius)));
  std::unordered_map<std::size_t, double> best;  // road → distance of its paved area from p
  for (const auto& [box, entry] : found) {
    if (!entry.is_road) continue;
    const Road& road = impl_->data.roads[entry.index];
    const double d = std::max(0.0, road.centerline.segment(entry.segment).distanceTo(p) - road.width / 2);
    if (d > radius) continue;
    auto [it, inserted] = best.emplace(entry.index, d);
    if (!inserted) it->second = std::min(it->second, d);
  }
  std::vector<std::pair<double, const Road*>> sorted;
  for (const auto& [index, d] : best) sorted.emplace_back(d, &impl_->data.roads[index]);
  std::sort(sorted.begin(), sorted.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first < b.first : a.second->id < b.second->id;
  });
  std::vector<const Road*> out;
  for (const auto& entry : sorted) out.push_back(entry.second);
  return out;
}

std::vector<const Road*> Map::roadsMeeting(const Polygon2& polygon) const {
  const auto found = impl_->candidates(polygonBounds(polygon));
  std::vector<const Road*> out;
  for (const auto& [box, entry] : found) {
    if (!entry.is_road) continue;
    const Road* road = &impl_->data.roads[entry.index];
    if (std::find(out.begin(), out.end(), road) != out.end()) continue;
    if (segmentNearPolygon(road->centerline.segment(entry.segment), road->width / 2, polygon)) out.push_back(road);
  }
  std::sort(out.begin(), out.end(), [](const Road* a, const Road* b) { return a->id < b->id; });
  return out;
}

std::vector<const Intersection*> Map::intersectionsMeeting(const Polygon2& polygon) const {
  const auto found = impl_->candidates(polygonBounds(polygon));
  std::vector<const Intersection*> out;
  for (const auto& [box, entry] : found) {
    if (entry.is_road) continue;
    const Polygon2& shape = impl_->shapes[entry.index];
    bool meets = contains(polygon, shape.front()) || contains(shape, polygon.front());
    for (std::size_t i = 0; i < shape.size() && !meets; ++i) {
      const Segment2 edge{shape[i], shape[(i + 1) % shape.size()]};
      meets = segmentNearPolygon(edge, 0.0, polygon);
    }
    if (meets) out.push_back(&impl_->data.intersections[entry.index]);
  }
  std::sort(out.begin(), out.end(), [](const Intersection* a, const Intersection* b) { return a->id < b->id; });
  return out;
}

std::vector<const Landmark*> Map::landmarksIn(const Polygon2& polygon) const {
  std::vector<std::pair<spatial::BPoint, std::size_t>> found;
  impl_->landmark_tree.query(bgi::intersects(toBBox(polygonBounds(polygon))), std::back_inserter(found));
  std::sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  std::vector<const Landmark*> out;
  for (const auto& [point, index] : found) {
    if (contains(polygon, impl_->data.landmarks[index].position)) out.push_back(&impl_->data.landmarks[index]);
  }
  return out;
}

const Road* Map::roadBeside(const Landmark& landmark) const {
  if (!landmark.road.empty()) return findRoad(landmark.road);
  // Widen the search until a road is found: the first radius that finds one finds the nearest.
  // Coordinates are within ±1e7 m (validation), so 1e8 m reaches every road.
  for (double radius = 5.0; radius < 1e9; radius *= 4) {
    const auto near = roadsNear(landmark.position, radius);
    if (!near.empty()) return near.front();
  }
  return nullptr;
}

Box2 Map::bounds() const { return impl_->bounds; }

const std::vector<std::vector<std::size_t>>& Map::components() const { return impl_->components; }

}  // namespace mapnav
