#include "mapnav/map/validation.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <map>
#include <unordered_map>
#include <set>
#include <unordered_set>

#include "mapnav/core/error.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/core/json.h"
#include "mapnav/geometry/polygon.h"
#include "spatial_internal.h"

namespace mapnav {

namespace bgi = boost::geometry::index;

const OptionTable<ValidationOptions>& validationOptionTable() {
  using O = ValidationOptions;
  static const OptionTable<O> table =
      OptionTable<O>("ValidationOptions")
          .field("end_tolerance_m", &O::end_tolerance_m, atLeast(0),
                 "how far a road's end may be from its intersection's position outside its shape, m")
          .field("repeated_point_tolerance_m", &O::repeated_point_tolerance_m, atLeast(0),
                 "consecutive centre-line points closer than this are a repeated point, m")
          .field("min_road_length_m", &O::min_road_length_m, atLeast(0), "shorter roads get roads.very_short, m")
          .field("max_coordinate_m", &O::max_coordinate_m, above(0),
                 "coordinates beyond +- this are refused (geometry.invalid_coordinate), m")
          .field("max_width_m", &O::max_width_m, above(0), "widths above this are refused (roads.invalid_width), m")
          .field("max_landmark_distance_m", &O::max_landmark_distance_m, atLeast(0),
                 "a landmark farther than this from its road's paved area gets landmarks.far_from_road, m");
  return table;
}

void ValidationOptions::validate() const { validationOptionTable().validate(*this); }

namespace {

std::string fmt(double x) {
  std::ostringstream text;
  text.precision(6);
  text << x;
  return text.str();
}

std::string fmt(const Vec2& p) { return "(" + fmt(p.x()) + ", " + fmt(p.y()) + ")"; }

bool validId(const std::string& id) {
  if (id.empty() || id.size() > 64 || !std::isalpha(static_cast<unsigned char>(id[0]))) return false;
  return std::all_of(id.begin(), id.end(), [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
  });
}

// The degrees of freedom a kind allows: minimum and maximum number of road ends.
std::pair<std::size_t, std::size_t> degreeRange(IntersectionKind kind) {
  switch (kind) {
    case IntersectionKind::End: return {1, 1};
    case IntersectionKind::L: return {2, 2};
    case IntersectionKind::T:
    case IntersectionKind::Y: return {3, 3};
    case IntersectionKind::Cross: return {4, 4};
    case IntersectionKind::Plaza: return {3, SIZE_MAX};
    case IntersectionKind::Other: return {0, SIZE_MAX};
  }
  return {0, SIZE_MAX};
}

class Validator {
 public:
  Validator(const MapData& map, const ValidationOptions& options) : map_(map), options_(options) {}

  Issues run() {
    checkIds();
    checkCoordinates();
    checkIntersections();
    checkRoads();
    checkCrossings();
    checkTopology();
    checkLandmarks();
    return std::move(issues_);
  }

 private:
  const MapData& map_;
  const ValidationOptions& options_;
  Issues issues_;
  std::unordered_map<std::string, std::size_t> intersection_index_;
  std::vector<bool> road_geometry_ok_;          // finite coordinates, >= 2 points
  std::vector<bool> intersection_geometry_ok_;  // finite position and shape

  void error(std::string check, std::string where, std::string message) {
    addIssue(issues_, Severity::Error, std::move(check), std::move(where), std::move(message));
  }
  void warning(std::string check, std::string where, std::string message) {
    addIssue(issues_, Severity::Warning, std::move(check), std::move(where), std::move(message));
  }
  static std::string roadPtr(std::size_t i) { return pointerJoin("/roads", i); }
  static std::string xPtr(std::size_t i) { return pointerJoin("/intersections", i); }
  static std::string landmarkPtr(std::size_t i) { return pointerJoin("/landmarks", i); }

  void checkIds() {
    std::unordered_map<std::string, std::string> seen;  // id → pointer of its first use
    auto check = [&](const std::string& id, const std::string& ptr) {
      if (!validId(id)) {
        error("schema.id", ptr, "id \"" + id + "\" must be a letter followed by letters, digits, '_' or '-' (at most 64)");
        return;
      }
      const auto [it, inserted] = seen.emplace(id, ptr);
      if (!inserted) error("ids.duplicate", ptr, "id \"" + id + "\" is already used at " + it->second);
    };
    for (std::size_t i = 0; i < map_.intersections.size(); ++i) {
      check(map_.intersections[i].id, xPtr(i) + "/id");
      intersection_index_.emplace(map_.intersections[i].id, i);
    }
    for (std::size_t i = 0; i < map_.roads.size(); ++i) check(map_.roads[i].id, roadPtr(i) + "/id");
    for (std::size_t i = 0; i < map_.landmarks.size(); ++i) check(map_.landmarks[i].id, landmarkPtr(i) + "/id");
  }

  bool pointOk(const Vec2& p, const std::string& ptr) {
    if (std::isfinite(p.x()) && std::isfinite(p.y()) && std::abs(p.x()) <= options_.max_coordinate_m &&
        std::abs(p.y()) <= options_.max_coordinate_m) {
      return true;
    }
    error("geometry.invalid_coordinate", ptr,
          "point " + fmt(p) + " is not finite or beyond ±" + fmt(options_.max_coordinate_m) + " m");
    return false;
  }

  void checkCoordinates() {
    intersection_geometry_ok_.assign(map_.intersections.size(), true);
    for (std::size_t i = 0; i < map_.intersections.size(); ++i) {
      const Intersection& x = map_.intersections[i];
      bool ok = pointOk(x.position, xPtr(i) + "/position");
      if (x.shape) {
        for (std::size_t k = 0; k < x.shape->size(); ++k) ok = pointOk((*x.shape)[k], pointerJoin(xPtr(i) + "/shape", k)) && ok;
      }
      intersection_geometry_ok_[i] = ok;
    }
    road_geometry_ok_.assign(map_.roads.size(), true);
    for (std::size_t i = 0; i < map_.roads.size(); ++i) {
      const auto& points = map_.roads[i].centerline.points();
      bool ok = true;
      for (std::size_t k = 0; k < points.size(); ++k) ok = pointOk(points[k], pointerJoin(roadPtr(i) + "/centerline", k)) && ok;
      road_geometry_ok_[i] = ok;
    }
  }

  void checkIntersections() {
    for (std::size_t i = 0; i < map_.intersections.size(); ++i) {
      const Intersection& x = map_.intersections[i];
      if (!x.shape || !intersection_geometry_ok_[i]) continue;
      const std::string ptr = xPtr(i) + "/shape";
      if (x.shape->size() < 3) {
        error("intersections.too_few_points", ptr, "a shape needs at least 3 points, it has " + std::to_string(x.shape->size()));
        intersection_geometry_ok_[i] = false;
      } else if (convexHull(*x.shape).size() < 3) {  // all on one line: the outline folds back on itself
        error("intersections.self_intersecting_shape", ptr,
              "the outline of intersection \"" + x.id + "\" encloses no area: its points lie on one line");
        intersection_geometry_ok_[i] = false;
      } else if (!isSimple(*x.shape)) {
        error("intersections.self_intersecting_shape", ptr, "the outline of intersection \"" + x.id + "\" crosses itself");
        intersection_geometry_ok_[i] = false;
      }
    }
  }

  std::optional<std::size_t> intersectionOf(const std::string& id) const {
    const auto it = intersection_index_.find(id);
    if (it == intersection_index_.end()) return std::nullopt;
    return it->second;
  }

  // Is p at intersection x: within the tolerance of its position, or inside (or near) its shape?
  bool atIntersection(std::size_t x, const Vec2& p) const {
    const Intersection& node = map_.intersections[x];
    if ((p - node.position).norm() <= options_.end_tolerance_m) return true;
    return node.shape && intersection_geometry_ok_[x] &&
           (contains(*node.shape, p) || boundaryDistance(*node.shape, p) <= options_.end_tolerance_m);
  }

  // A map's or a road's position_sigma_m: finite, in [0, kMaxPositionSigmaM].
  void checkPositionSigma(double sigma, const std::string& ptr) {
    if (!std::isfinite(sigma) || sigma < 0 || sigma > kMaxPositionSigmaM) {
      error("schema.range", ptr, "position_sigma_m " + fmt(sigma) + " must be >= 0 and <= " + fmt(kMaxPositionSigmaM) + " m");
    }
  }

  void checkRoads() {
    checkPositionSigma(map_.position_sigma_m, "/position_sigma_m");
    std::unordered_set<std::string> surfaces;
    for (const auto& [name, appearance] : map_.surfaces) surfaces.insert(name);
    for (std::size_t i = 0; i < map_.roads.size(); ++i) {
      const Road& road = map_.roads[i];
      const std::string ptr = roadPtr(i);
      for (const auto& [member, value] : {std::pair{"from", &road.from}, std::pair{"to", &road.to}}) {
        if (!intersectionOf(*value)) {
          error("roads.unknown_intersection", ptr + "/" + member,
                "road \"" + road.id + "\" " + member + " \"" + *value + "\": no intersection has this id");
        }
      }
      if (!std::isfinite(road.width) || road.width <= 0 || road.width > options_.max_width_m) {
        const auto [width, widest] = comparedText(road.width, options_.max_width_m);
        error("roads.invalid_width", ptr + "/width", "width " + width + " m must be > 0 and <= " + widest + " m");
      }
      if (!std::isfinite(road.cost_factor) || road.cost_factor <= 0) {
        error("schema.range", ptr + "/cost_factor", "cost_factor " + fmt(road.cost_factor) + " must be > 0");
      }
      if (road.position_sigma_m) checkPositionSigma(*road.position_sigma_m, ptr + "/position_sigma_m");
      for (const auto& [member, value] :
           {std::pair{"surface", &road.surface}, std::pair{"left", &road.left}, std::pair{"right", &road.right}}) {
        if (!surfaces.contains(*value)) {
          error("surfaces.unknown", ptr + "/" + member, "surface \"" + *value + "\" is not in \"surfaces\"");
        }
      }
      checkRoadGeometry(i);
    }
  }

  void checkRoadGeometry(std::size_t i) {
    const Road& road = map_.roads[i];
    const std::string ptr = roadPtr(i) + "/centerline";
    const auto& points = road.centerline.points();
    if (points.size() < 2) {
      error("roads.too_few_points", ptr, "a centerline needs at least 2 points, it has " + std::to_string(points.size()));
      road_geometry_ok_[i] = false;
    }
    if (!road_geometry_ok_[i]) return;
    bool repeated = false;
    for (std::size_t k = 1; k < points.size(); ++k) {
      if ((points[k] - points[k - 1]).norm() < options_.repeated_point_tolerance_m) {
        error("roads.repeated_point", pointerJoin(ptr, k), "point " + std::to_string(k) + " " + fmt(points[k]) + " repeats point " + std::to_string(k - 1));
        repeated = true;
      }
    }
    for (const auto& [member, end] : {std::pair{std::string("from"), std::size_t{0}}, std::pair{std::string("to"), points.size() - 1}}) {
      const auto x = intersectionOf(member == "from" ? road.from : road.to);
      if (!x || !intersection_geometry_ok_[*x]) continue;
      if (!atIntersection(*x, points[end])) {
        const Intersection& node = map_.intersections[*x];
        error("roads.end_far_from_intersection", pointerJoin(ptr, end),
              "road \"" + road.id + "\" " + (end == 0 ? "starts" : "ends") + " at " + fmt(points[end]) + ", " +
                  fmt((points[end] - node.position).norm()) + " m from intersection \"" + node.id + "\" at " +
                  fmt(node.position) + " (tolerance " + fmt(options_.end_tolerance_m) + " m)");
      }
    }
    if (!repeated) {
      // A loop road that comes back to its first point: its first and last segments meet there
      // as neighbours do, not as a crossing.
      const bool closed = points.size() > 3 && (points.front() - points.back()).norm() < options_.repeated_point_tolerance_m;
      const std::vector<Vec2> chain(points.begin(), closed ? points.end() - 1 : points.end());
      for (const SegmentHit& hit : selfIntersections(chain, closed)) {
        error("roads.self_intersection", pointerJoin(ptr, std::min(hit.i, hit.j)),
              "segment " + std::to_string(std::min(hit.i, hit.j)) + " of road \"" + road.id + "\" meets its segment " +
                  std::to_string(std::max(hit.i, hit.j)) + " at " + fmt(hit.point));
      }
    }
    if (road.centerline.length() < options_.min_road_length_m) {
      const auto [length, least] = comparedText(road.centerline.length(), options_.min_road_length_m);
      warning("roads.very_short", ptr, "road \"" + road.id + "\" is " + length + " m long (< " + least + " m)");
    }
  }

  // Landmarks: a size that makes sense, a road that exists, standing beside it (not on its paving,
  // not far from it). Distances are to the paved areas of roads with valid geometry, found through
  // an R-tree of their segments, so the cost grows with the roads near each landmark.
  void checkLandmarks() {
    if (map_.landmarks.empty()) return;
    using Value = std::pair<spatial::BBox, std::pair<std::size_t, std::size_t>>;  // (road, segment)
    std::vector<Value> values;
    double widest = 0;
    std::unordered_map<std::string, std::size_t> road_index;
    for (std::size_t r = 0; r < map_.roads.size(); ++r) {
      road_index.emplace(map_.roads[r].id, r);
      if (!road_geometry_ok_[r] || !std::isfinite(map_.roads[r].width)) continue;
      widest = std::max(widest, map_.roads[r].width);
      const Polyline2& c = map_.roads[r].centerline;
      for (std::size_t s = 0; s < c.segmentCount(); ++s) values.emplace_back(spatial::toBBox(c.segment(s).bounds()), std::pair{r, s});
    }
    const bgi::rtree<Value, bgi::rstar<16>> tree(values.begin(), values.end());
    for (std::size_t i = 0; i < map_.landmarks.size(); ++i) {
      const Landmark& l = map_.landmarks[i];
      const std::string ptr = landmarkPtr(i);
      if (!pointOk(l.position, ptr + "/position")) continue;
      checkLandmarkSize(l, ptr);
      std::optional<std::size_t> named;
      if (!l.road.empty()) {
        const auto it = road_index.find(l.road);
        if (it == road_index.end()) {
          error("landmarks.unknown_road", ptr + "/road", "landmark \"" + l.id + "\" road \"" + l.road + "\": no road has this id");
          continue;
        }
        named = it->second;
      }
      // Distance (m) from the landmark's centre to each nearby road's paved area (< 0: inside it).
      const double reach = options_.max_landmark_distance_m + widest / 2 + std::max(l.radius, 0.0);
      const Box2 box(l.position - Vec2::Constant(reach), l.position + Vec2::Constant(reach));
      std::vector<Value> found;
      tree.query(bgi::intersects(spatial::toBBox(box)), std::back_inserter(found));
      std::map<std::size_t, double> distance;  // road → distance, ordered for a stable report
      for (const Value& v : found) {
        const auto [r, s] = v.second;
        const double d = map_.roads[r].centerline.segment(s).distanceTo(l.position) - map_.roads[r].width / 2;
        auto [it, inserted] = distance.emplace(r, d);
        if (!inserted) it->second = std::min(it->second, d);
      }
      if (isUpright(l.kind)) {
        for (const auto& [r, d] : distance) {
          if (d >= landmarkHalfWidth(l)) continue;
          warning("landmarks.on_paved_area", ptr + "/position",
                  "landmark \"" + l.id + "\" (a " + std::string(toString(l.kind)) + ") stands on road \"" +
                      map_.roads[r].id + "\"'s paved area: a vehicle there would have to pass it");
          break;
        }
      }
      const auto beside = named ? distance.find(*named) : std::min_element(distance.begin(), distance.end(), [](const auto& a, const auto& b) {
        return a.second < b.second;
      });
      if (beside == distance.end() || beside->second > options_.max_landmark_distance_m) {
        const std::string road = named ? "its road \"" + l.road + "\"" : "every road";
        warning("landmarks.far_from_road", ptr + "/position",
                "landmark \"" + l.id + "\" is more than " + fmt(options_.max_landmark_distance_m) + " m from " + road +
                    ": a camera on the road would hardly see it");
      }
    }
  }

  void checkLandmarkSize(const Landmark& l, const std::string& ptr) {
    if (!std::isfinite(l.radius) || l.radius <= 0 || l.radius > 10) {
      error("landmarks.invalid_size", ptr + "/radius", "radius " + fmt(l.radius) + " m must be > 0 and <= 10 m");
    }
    const bool upright = isUpright(l.kind);
    if (!std::isfinite(l.height) || l.height < 0 || l.height > 100 || (upright && l.height == 0) || (!upright && l.height != 0)) {
      error("landmarks.invalid_size", ptr + "/height",
            "height " + fmt(l.height) + " m of a " + std::string(toString(l.kind)) + " must be " +
                (upright ? "> 0 and <= 100 m" : "0 (it lies flat)"));
    }
  }

  // Roads on the same layer crossing each other away from every intersection they share (roads on
  // different layers pass over and under each other). One R-tree over all
  // segments, so the cost grows with the segments that are close, not with the square of the map.
  void checkCrossings() {
    using Value = std::pair<spatial::BBox, std::pair<std::size_t, std::size_t>>;  // (road, segment)
    std::vector<Value> values;
    for (std::size_t r = 0; r < map_.roads.size(); ++r) {
      if (!road_geometry_ok_[r]) continue;
      const Polyline2& c = map_.roads[r].centerline;
      for (std::size_t s = 0; s < c.segmentCount(); ++s) {
        if (c.segment(s).length() < options_.repeated_point_tolerance_m) continue;  // reported as repeated
        values.emplace_back(spatial::toBBox(c.segment(s).bounds()), std::pair{r, s});
      }
    }
    const bgi::rtree<Value, bgi::rstar<16>> tree(values.begin(), values.end());
    std::set<std::pair<std::size_t, std::size_t>> reported;  // road pairs
    std::vector<Value> found;
    for (const Value& v : values) {
      const auto [r, s] = v.second;
      found.clear();
      tree.query(bgi::intersects(v.first), std::back_inserter(found));
      std::sort(found.begin(), found.end(), [](const Value& a, const Value& b) { return a.second < b.second; });
      for (const Value& w : found) {
        const auto [q, t] = w.second;
        if (q <= r || reported.contains({r, q})) continue;
        if (map_.roads[r].layer != map_.roads[q].layer) continue;  // a bridge over, a tunnel under
        const Segment2 a = map_.roads[r].centerline.segment(s), b = map_.roads[q].centerline.segment(t);
        if (!segmentsIntersect(a, b)) continue;
        const Vec2 p = meetingPoint(a, b);
        if (atSharedIntersection(r, q, p)) continue;
        reported.insert({r, q});
        error("roads.crossing_without_intersection", pointerJoin(roadPtr(r) + "/centerline", s),
              "road \"" + map_.roads[r].id + "\" crosses road \"" + map_.roads[q].id + "\" at " + fmt(p) +
                  " where there is no intersection they share");
      }
    }
  }

  static Vec2 meetingPoint(const Segment2& a, const Segment2& b) {
    if (const auto p = segmentIntersection(a, b)) return *p;
    // Collinear overlap: one of the end points lies on the other segment.
    for (const Vec2& p : {a.a, a.b}) {
      if (b.distanceTo(p) < 1e-9) return p;
    }
    return b.a;
  }

  bool atSharedIntersection(std::size_t r, std::size_t q, const Vec2& p) const {
    const Road& a = map_.roads[r];
    const Road& b = map_.roads[q];
    for (const std::string* x : {&a.from, &a.to}) {
      if (*x != b.from && *x != b.to) continue;
      const auto index = intersectionOf(*x);
      if (index && atIntersection(*index, p)) return true;
    }
    return false;
  }

  void checkTopology() {
    const std::size_t n = map_.intersections.size();
    std::vector<std::size_t> degree(n, 0);
    std::vector<std::pair<std::size_t, std::size_t>> edges;
    for (const Road& road : map_.roads) {
      const auto a = intersectionOf(road.from), b = intersectionOf(road.to);
      if (a) ++degree[*a];
      if (b) ++degree[*b];
      if (a && b) edges.emplace_back(*a, *b);
    }
    for (std::size_t i = 0; i < n; ++i) {
      const Intersection& x = map_.intersections[i];
      const auto [lo, hi] = degreeRange(x.kind);
      if (degree[i] < lo || degree[i] > hi) {
        warning("intersections.kind_mismatch", xPtr(i) + "/kind",
                "intersection \"" + x.id + "\" is a \"" + std::string(toString(x.kind)) + "\" but " +
                    std::to_string(degree[i]) + " road ends meet there");
      }
    }
    // The first intersection (in file order) of every piece but intersections[0]'s is reported.
    const std::vector<std::size_t> label = spatial::componentLabels(n, edges);
    for (std::size_t i = 0; i < n; ++i) {
      if (label[i] != i || label[i] == 0) continue;
      warning("topology.disconnected", xPtr(i),
              "intersection \"" + map_.intersections[i].id + "\" cannot be reached from \"" +
                  map_.intersections[0].id + "\": the network falls apart");
    }
  }
};

}  // namespace

Issues validateMap(const MapData& map, const ValidationOptions& options) {
  options.validate();
  return Validator(map, options).run();
}

}  // namespace mapnav
