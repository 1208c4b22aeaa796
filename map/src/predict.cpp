#include "mapnav/map/predict.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <unordered_map>

#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/geometry/clip.h"
#include "mapnav/geometry/polygon.h"
#include "mapnav/geometry/simplify.h"
#include "mapnav/tokens/token_json.h"

namespace mapnav {

const OptionTable<PredictOptions>& predictOptionTable() {
  using O = PredictOptions;
  static const OptionTable<O> table =
      OptionTable<O>("PredictOptions")
          .field("near_m", &O::near_m, atLeast(0), "the footprint: ground in view at least this far ahead of the camera, m")
          .field("far_m", &O::far_m, "... and at most this far from it, m")
          .field("simplify_tolerance_m", &O::simplify_tolerance_m, above(0),
                 "curved edges become straight pieces within this of the curve, m")
          .field("min_segment_length_m", &O::min_segment_length_m, atLeast(0),
                 "segments shorter than this on the ground are dropped, m")
          .field("min_segment_length_px", &O::min_segment_length_px, atLeast(0),
                 "segments shorter than this in the image are dropped, px")
          .field("min_in_image_fraction", &O::min_in_image_fraction, inRange(0, 1),
                 "segments with less of their length inside the image are dropped")
          .field("parallel_tolerance_deg", &O::parallel_tolerance_deg, OptionRule{.min = 0, .max = 45, .max_open = true},
                 "segments within this angle of each other (degrees) ...")
          .field("max_parallel_separation_m", &O::max_parallel_separation_m, above(0),
                 "... and at most this far apart are a parallel pair, m")
          .field("crossing_min_angle_deg", &O::crossing_min_angle_deg, aboveUpTo(0, 90),
                 "segments at least this far apart in angle cross (degrees) ...")
          .field("crossing_reach_m", &O::crossing_reach_m, atLeast(0), "... where their lines meet within this of both, m")
          .check("far_m", [](const O& o) { return o.far_m > o.near_m; }, "> near_m")
          .check("crossing_min_angle_deg", [](const O& o) { return o.crossing_min_angle_deg > o.parallel_tolerance_deg; },
                 "> parallel_tolerance_deg");
  return table;
}

void PredictOptions::validate() const { predictOptionTable().validate(*this); }

std::string regionKind(IntersectionKind kind) {
  switch (kind) {
    case IntersectionKind::Cross: return "cross intersection";
    case IntersectionKind::T: return "T intersection";
    case IntersectionKind::Y: return "Y intersection";
    case IntersectionKind::L: return "L turn";
    case IntersectionKind::End: return "dead end";
    case IntersectionKind::Plaza: return "plaza";
    case IntersectionKind::Other: return "junction";
  }
  return "junction";
}

std::string intersectionSurface(const Map& map, const Intersection& intersection) {
  const Road* widest = nullptr;
  for (const auto& end : map.roadsAt(intersection.id)) {
    if (widest == nullptr || end.road->width > widest->width) widest = end.road;
  }
  return widest == nullptr ? std::string() : widest->surface;
}

namespace {

// An interest segment in the world, before the view clips it.
// A tunnel is seen only from inside it (the vehicle on its paved width); everything else from anywhere.
bool canBeSeen(const Road& road, const Vec2& vehicle) {
  return road.structure != RoadStructure::Tunnel || road.centerline.project(vehicle).distance <= road.width / 2;
}

struct MapSegment {
  std::string id, owner, side;
  Segment2 world;
  std::string left_surface, right_surface;
};

class Predictor {
 public:
  Predictor(const Map& map, const PredictOptions& options) : map_(map), options_(options) {}

  // Paved areas near `area` other than `self` (a road or intersection), which cover edges.
  std::vector<Polygon2> pavedNear(const Polygon2& area, const std::string& self) const {
    std::vector<Polygon2> out;
    for (const Road* road : map_.roadsMeeting(area)) {
      if (road->id != self) out.push_back(map_.roadPolygon(*road));
    }
    for (const Intersection* x : map_.intersectionsMeeting(area)) {
      if (x->id != self) out.push_back(map_.intersectionShape(*x));
    }
    return out;
  }

  // A road side, simplified into straight pieces, less what other paved areas cover, numbered.
  std::vector<MapSegment> roadSegments(const Road& road) const {
    const std::vector<Polygon2> covers = pavedNear(map_.roadPolygon(road), road.id);
    std::vector<const Polygon2*> rings;
    for (const Polygon2& p : covers) rings.push_back(&p);
    std::vector<MapSegment> out;
    for (const bool left : {true, false}) {
      const Polyline2& edge = left ? map_.leftEdge(road) : map_.rightEdge(road);
      const std::vector<Vec2> points = simplifyPolyline(edge.points(), options_.simplify_tolerance_m);
      const std::string side = left ? "left" : "right";
      std::size_t index = 0;
      for (std::size_t k = 0; k + 1 < points.size(); ++k) {
        const Segment2 piece{points[k], points[k + 1]};
        for (const Interval& part : intervalsOutside(piece, rings)) {
          MapSegment s;
          s.id = road.id + "." + side + "." + std::to_string(index++);
          s.owner = road.id;
          s.side = side;
          s.world = Segment2{piece.pointAt(part.first), piece.pointAt(part.second)};
          s.left_surface = left ? road.left : road.surface;
          s.right_surface = left ? road.surface : road.right;
          out.push_back(std::move(s));
        }
      }
    }
    return out;
  }

  // An intersection's outline less what its roads cover or run along: the corners between roads.
  std::vector<MapSegment> cornerSegments(const Intersection& x) const {
    const Polygon2& shape = map_.intersectionShape(x);
    std::vector<Polygon2> covers;
    std::vector<const Road*> roads = map_.roadsMeeting(shape);
    for (const Road* road : roads) covers.push_back(map_.roadPolygon(*road));
    std::vector<const Polygon2*> rings;
    for (const Polygon2& p : covers) rings.push_back(&p);
    auto onRoadEdge = [&](const Segment2& part) {
      for (const Road* road : roads) {
        for (const Polyline2* edge : {&map_.leftEdge(*road), &map_.rightEdge(*road)}) {
          if (edge->project(part.a).distance < 1e-3 && edge->project(part.b).distance < 1e-3 &&
              edge->project(part.pointAt(0.5)).distance < 1e-3) {
            return true;
          }
        }
      }
      return false;
    };
    // What is paved here, and the shoulder most of its roads have.
    const auto ends = map_.roadsAt(x.id);
    const std::string paved = intersectionSurface(map_, x);
    std::map<std::string, int> votes;
    for (const auto& e : ends) {
      ++votes[e.road->left];
      ++votes[e.road->right];
    }
    const auto best = std::max_element(votes.begin(), votes.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
    const std::string shoulder = best == votes.end() ? std::string() : best->first;

    std::vector<MapSegment> out;
    std::size_t index = 0;
    for (std::size_t k = 0; k < shape.size(); ++k) {
      const Segment2 edge{shape[k], shape[(k + 1) % shape.size()]};
      for (const Interval& part : intervalsOutside(edge, rings)) {
        const Segment2 piece{edge.pointAt(part.first), edge.pointAt(part.second)};
        if (piece.length() < 1e-6 || onRoadEdge(piece)) continue;
        // The shape is counter-clockwise, so the paved inside is on the left.
        out.push_back(MapSegment{x.id + ".corner." + std::to_string(index++), x.id, "corner", piece, paved, shoulder});
      }
    }
    return out;
  }

 private:
  const Map& map_;
  const PredictOptions& options_;
};

// A road's paved area as simple polygons for clipping: the road polygon itself, or, for a road bent
// tighter than its half width (whose outline then crosses itself), the quadrilaterals between its
// consecutive cross-sections (the polygon is the left edge, then the right edge reversed).
std::vector<Polygon2> simplePieces(const Polygon2& ring) {
  if (isSimple(ring)) return {ring};
  std::vector<Polygon2> quads;
  const std::size_t n = ring.size() / 2;
  for (std::size_t k = 0; k + 1 < n; ++k) {
    Polygon2 quad{ring[k], ring[k + 1], ring[ring.size() - 2 - k], ring[ring.size() - 1 - k]};
    if (isSimple(quad)) quads.push_back(std::move(quad));
  }
  return quads;
}

Vec3 colourOf(const Map& map, const std::string& surface) {
  const Appearance* a = map.findSurface(surface);
  return a ? a->rgb : Vec3::Zero();
}

void addRelations(PredictedObject& view, const PredictOptions& options) {
  const double parallel = degToRad(options.parallel_tolerance_deg);
  const double crossing = degToRad(options.crossing_min_angle_deg);
  const auto& segs = view.segments;
  for (std::size_t i = 0; i < segs.size(); ++i) {
    for (std::size_t j = i + 1; j < segs.size(); ++j) {
      const Segment2 &a = segs[i].vehicle, &b = segs[j].vehicle;
      const double angle = angleBetweenLines(a, b);
      if (angle <= parallel) {
        // Parallel when they run side by side (their extents along a overlap) on different lines.
        // Two pieces of one polyline meet end to end: their overlap is zero but for rounding, and
        // whether a kink's two sides made a pair turned on the last bit of the pose. Side by side
        // means for at least kMinParallelOverlapM.
        constexpr double kMinParallelOverlapM = 0.1;
        const double len = a.length();
        const Vec2 d = a.direction();
        const double t0 = (b.a - a.a).dot(d), t1 = (b.b - a.a).dot(d);
        const double overlap = std::min(len, std::max(t0, t1)) - std::max(0.0, std::min(t0, t1));
        const double separation = std::abs(a.signedDistance(b.pointAt(0.5)));
        if (overlap > kMinParallelOverlapM && separation > 1e-3 && separation <= options.max_parallel_separation_m) {
          view.relations.push_back({SegmentRelation::Type::Parallel, segs[i].id, segs[j].id, separation, angle, Vec2::Zero()});
        }
      } else if (angle >= crossing) {
        // Where the lines meet (a.a + s (a.b − a.a) = b.a + t (b.b − b.a)).
        const Vec2 r = a.vector(), q = b.vector();
        const double denom = cross2(r, q);
        if (std::abs(denom) < 1e-12) continue;
        const Vec2 p = a.a + (cross2(b.a - a.a, q) / denom) * r;
        if (a.distanceTo(p) <= options.crossing_reach_m && b.distanceTo(p) <= options.crossing_reach_m) {
          view.relations.push_back({SegmentRelation::Type::Crossing, segs[i].id, segs[j].id, 0.0, angle, p});
        }
      }
    }
  }
}

// The fraction of a ground segment (vehicle frame) whose points fall inside the image.
double inImageFraction(const Camera& camera, const Segment2& s) {
  constexpr int kSamples = 11;
  int inside = 0;
  for (int i = 0; i < kSamples; ++i) {
    const auto px = camera.projectGround(s.pointAt(i / double(kSamples - 1)));
    inside += px && camera.inImage(*px) ? 1 : 0;
  }
  return inside / double(kSamples);
}

// The footprint within `far` metres of the camera: the largest piece of its intersection with a
// 96-gon around the optical centre (the polygon lies inside the circle, so nothing beyond is kept).
Polygon2 withinRange(const Polygon2& footprint, const Vec2& camera, double far) {
  Polygon2 disc;
  for (int i = 0; i < 96; ++i) disc.push_back(camera + far * unitVector(2 * kPi * i / 96));
  std::vector<Polygon2> pieces = intersectPolygons(footprint, disc);
  if (pieces.empty()) return {};
  return *std::max_element(pieces.begin(), pieces.end(), [](const Polygon2& a, const Polygon2& b) {
    return std::abs(signedArea(a)) < std::abs(signedArea(b));
  });
}

// The view footprint within range, in the vehicle frame.
Polygon2 vehicleFootprint(const Camera& camera, double near_m, double far_m) {
  Polygon2 footprint = viewFootprint(camera, near_m, far_m);
  if (footprint.size() >= 3) footprint = withinRange(footprint, camera.center().head<2>(), far_m);
  return footprint;
}

}  // namespace

// What a road or an intersection gives every view, whatever the pose.
struct ViewPredictor::Store {
  struct Parts {
    std::vector<Polygon2> pieces;      // its paved area as simple polygons (simplePieces)
    std::vector<Vec2> centre;          // a road's centre line in straight pieces (none for an intersection)
    std::vector<MapSegment> segments;  // its interest segments, in the world
  };
  std::unordered_map<const Road*, Parts> roads;
  std::unordered_map<const Intersection*, Parts> intersections;

  // The view footprint within range (vehicle frame) of the last camera: it depends on the camera
  // and the options' range alone, not on the pose, so it is kept while the camera stays the same.
  // Building it (an exact intersection with a 96-gon) was about a third of a frame's prediction.
  struct Footprint {
    LensModel model{};
    CameraIntrinsics intrinsics;
    CameraMount mount;
    Polygon2 ring;
  };
  std::optional<Footprint> footprint;

  const Polygon2& footprintOf(const Camera& camera, const PredictOptions& options) {
    if (!footprint || footprint->model != camera.model() || !(footprint->intrinsics == camera.intrinsics()) ||
        !(footprint->mount == camera.mount()))
      footprint = Footprint{camera.model(), camera.intrinsics(), camera.mount(),
                            vehicleFootprint(camera, options.near_m, options.far_m)};
    return footprint->ring;
  }

  const Parts& of(const Road& road, const Predictor& predictor, const Map& map, const PredictOptions& options) {
    if (const auto it = roads.find(&road); it != roads.end()) return it->second;
    Parts parts{simplePieces(map.roadPolygon(road)),
                simplifyPolyline(road.centerline.points(), options.simplify_tolerance_m), predictor.roadSegments(road)};
    return roads.emplace(&road, std::move(parts)).first->second;
  }
  const Parts& of(const Intersection& x, const Predictor& predictor, const Map& map) {
    if (const auto it = intersections.find(&x); it != intersections.end()) return it->second;
    Parts parts{simplePieces(map.intersectionShape(x)), {}, predictor.cornerSegments(x)};
    return intersections.emplace(&x, std::move(parts)).first->second;
  }
};

namespace {

// The landmarks whose ground contact point lies in the footprint and projects into the image,
// nearest the camera first (ties in the map's order).
void addLandmarks(const Map& map, const Pose2& pose, const Camera& camera, Prediction& out) {
  const Vec2 centre = camera.center().head<2>();
  struct InView {
    double range;
    Vec2 vehicle;
    const Landmark* landmark;
  };
  std::vector<InView> found;
  for (const Landmark* l : map.landmarksIn(out.footprint_world)) {
    const Vec2 vehicle = pose.inverseTransform(l->position);
    found.push_back({(vehicle - centre).norm(), vehicle, l});
  }
  std::stable_sort(found.begin(), found.end(), [](const InView& a, const InView& b) { return a.range < b.range; });
  for (const auto& [range, vehicle, l] : found) {
    const auto base = camera.projectGround(vehicle);
    const auto top = camera.project(Vec3(vehicle.x(), vehicle.y(), l->height));
    if (!base || !top || !camera.inImage(*base)) continue;
    PredictedLandmark p;
    p.id = l->id;
    p.kind = std::string(toString(l->kind));
    p.vehicle = vehicle;
    p.radius_m = l->radius;
    p.height_m = l->height;
    p.image_base = *base;
    p.image_top = *top;
    p.width_px = groundWidthPx(camera, vehicle, l->radius).value_or(0.0);
    out.view.landmarks.push_back(std::move(p));
    out.landmarks.push_back(l);
  }
}

}  // namespace

ViewPredictor::ViewPredictor(const Map& map, const PredictOptions& options)
    : map_(&map), options_(options), store_(std::make_unique<Store>()) {
  options_.validate();
}
ViewPredictor::~ViewPredictor() = default;
ViewPredictor::ViewPredictor(ViewPredictor&&) noexcept = default;
ViewPredictor& ViewPredictor::operator=(ViewPredictor&&) noexcept = default;

Prediction ViewPredictor::predict(const Pose2& pose, const Camera& camera) {
  const Map& map = *map_;
  const PredictOptions& options = options_;
  Prediction out;
  out.pose = pose;
  out.view.footprint = store_->footprintOf(camera, options);
  if (out.view.footprint.size() < 3) {
    out.view.footprint.clear();
    return out;
  }
  for (const Vec2& p : out.view.footprint) out.footprint_world.push_back(pose.transform(p));
  const Polygon2& footprint = out.footprint_world;
  const Predictor predictor(map, options);

  auto addRegion = [&](const std::string& id, const std::string& kind, const std::string& surface,
                       const Store::Parts& parts) {
    std::vector<Polygon2> world;
    for (const Polygon2& piece : parts.pieces) {
      // A pin-hole camera's footprint is convex: then the clip is a fast one in doubles.
      for (Polygon2& clipped : intersectWithConvex(piece, footprint)) world.push_back(std::move(clipped));
    }
    if (world.empty()) return;
    PredictedRegion region;
    region.id = id;
    region.kind = kind;
    region.surface = surface;
    region.rgb = colourOf(map, surface);
    for (const Polygon2& ring : world) {
      Polygon2 local;
      for (const Vec2& p : ring) local.push_back(pose.inverseTransform(p));
      region.vehicle.push_back(std::move(local));
    }
    // Clip the region's segments to the footprint; keep the long, mostly-in-image parts.
    for (const MapSegment& s : parts.segments) {
      std::vector<Interval> inside = intervalsInside(s.world, footprint);
      if (inside.empty()) continue;
      // A footprint that cuts a segment in two keeps its longest part under the segment's id.
      const Interval best = *std::max_element(inside.begin(), inside.end(), [](const Interval& a, const Interval& b) {
        return a.second - a.first < b.second - b.first;
      });
      const Segment2 world_part{s.world.pointAt(best.first), s.world.pointAt(best.second)};
      if (world_part.length() < options.min_segment_length_m) continue;
      const Segment2 vehicle{pose.inverseTransform(world_part.a), pose.inverseTransform(world_part.b)};
      const auto ua = camera.projectGround(vehicle.a), ub = camera.projectGround(vehicle.b);
      if (!ua || !ub || (*ua - *ub).norm() < options.min_segment_length_px) continue;
      if (inImageFraction(camera, vehicle) < options.min_in_image_fraction) continue;
      InterestSegment seg;
      seg.id = s.id;
      seg.owner = s.owner;
      seg.side = s.side;
      seg.vehicle = vehicle;
      seg.image = Segment2{*ua, *ub};
      seg.left_surface = s.left_surface;
      seg.right_surface = s.right_surface;
      seg.left_rgb = colourOf(map, s.left_surface);
      seg.right_rgb = colourOf(map, s.right_surface);
      region.segments.push_back(seg.id);
      out.view.segments.push_back(std::move(seg));
      out.segments_world.push_back(world_part);
    }
    out.view.regions.push_back(std::move(region));
    out.regions_world.push_back(std::move(world));
  };

  for (const Road* road : map.roadsMeeting(footprint)) {
    if (!canBeSeen(*road, pose.translation())) continue;
    const Store::Parts& parts = store_->of(*road, predictor, map, options);
    // A road is a curve in view when its centre line inside the footprint is more than one straight piece.
    int visible_pieces = 0;
    for (std::size_t k = 0; k + 1 < parts.centre.size(); ++k) {
      visible_pieces += intervalsInside(Segment2{parts.centre[k], parts.centre[k + 1]}, footprint).empty() ? 0 : 1;
    }
    addRegion(road->id, visible_pieces > 1 ? "curve" : "straight road", road->surface, parts);
  }
  for (const Intersection* x : map.intersectionsMeeting(footprint)) {
    addRegion(x->id, regionKind(x->kind), intersectionSurface(map, *x), store_->of(*x, predictor, map));
  }
  addRelations(out.view, options);
  addLandmarks(map, pose, camera, out);
  return out;
}

Prediction predictView(const Map& map, const Pose2& pose, const Camera& camera, const PredictOptions& options) {
  return ViewPredictor(map, options).predict(pose, camera);
}

std::string predictionToJson(const Prediction& p) {
  using namespace token_json;
  Json areas = Json::array();
  for (std::size_t r = 0; r < p.view.regions.size(); ++r) {
    Json rings = Json::array();
    for (const Polygon2& ring : p.regions_world[r]) rings.push_back(points(ring, metres));
    areas.push_back({{"id", p.view.regions[r].id}, {"area", std::move(rings)}});
  }
  Json segments = Json::array();
  for (std::size_t i = 0; i < p.view.segments.size(); ++i)
    segments.push_back({{"id", p.view.segments[i].id}, {"world", segment(p.segments_world[i], metres)}});
  Json landmarks = Json::array();
  for (std::size_t i = 0; i < p.view.landmarks.size(); ++i)
    landmarks.push_back({{"id", p.view.landmarks[i].id}, {"world", point(p.landmarks[i]->position, metres)}});
  return dumpJson(Json{{"pose", pose(p.pose)},
                       {"view", toJson(p.view)},
                       {"world",
                        {{"footprint", points(p.footprint_world, metres)},
                         {"regions", std::move(areas)},
                         {"segments", std::move(segments)},
                         {"landmarks", std::move(landmarks)}}}});
}

}  // namespace mapnav
