#include "mapnav/vision/line_labelling.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numbers>

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "mapnav/geometry/simplify.h"

namespace mapnav {

const OptionTable<LineOptions>& lineOptionTable() {
  using O = LineOptions;
  static const OptionTable<O> table =
      OptionTable<O>("LineOptions")
          .field("simplify_tolerance_px", &O::simplify_tolerance_px, aboveUpTo(0, 100), "polygon fit tolerance, pixels")
          .field("min_length_px", &O::min_length_px, inRange(0, 1e6), "shorter polygon edges are dropped, pixels")
          .field("frame_edge_px", &O::frame_edge_px, inRange(0, 100),
                 "lines within this of the image border or ground edge are frame edges, pixels")
          .field("max_angle_deg", &O::max_angle_deg, aboveUpTo(0, 90), "label match: angle on the ground within this")
          .field("max_distance_m", &O::max_distance_m, aboveUpTo(0, 100),
                 "label match: both end points within this of the predicted line (the gate's floor)")
          .field("gate_sigma", &O::gate_sigma, inRange(0, 100),
                 "label match: ... or within this many sigma of it, the predicted line's sigma across itself from the "
                 "prediction's pose covariance (the Map's estimate), where that is wider, but no "
                 "further than halfway to the neighbouring predicted segment, on a map that states no error (the "
                 "prediction's map_sigma_m 0); 0 = max_distance_m alone")
          .field("gate_sigma_uncertain_map", &O::gate_sigma_uncertain_map, inRange(0, 100),
                 "gate_sigma where the prediction's map states an error (map_sigma_m > 0)")
          .field("min_overlap", &O::min_overlap, inRange(0, 1),
                 "label match: this fraction of the line overlaps the predicted segment")
          .field("relation_tolerance_m", &O::relation_tolerance_m, aboveUpTo(0, 100),
                 "a labelled parallel pair must be within this of the predicted separation")
          .field("reference", &O::reference,
                 "the reference implementations (CGAL's simplification, a distance transform for the frame edges) "
                 "instead of the fast ones with the same answers");
  return table;
}

void LineOptions::validate() const { lineOptionTable().validate(*this); }

namespace {

// Drops a ring's repeated closing point; whether it had one.
bool dropClosingPoint(std::vector<Vec2>& ring) {
  if (!(ring.size() >= 2 && (ring.front() - ring.back()).norm() < 1e-9)) return false;
  ring.pop_back();
  return true;
}

// contourPolygon's last step: `poly`, the closed contour simplified within `tolerance_px` (its
// first point repeated last), as the polygon contourPolygon gives.
std::vector<Vec2> ringPolygon(std::vector<Vec2> poly, double tolerance_px) {
  // The ring's start is an arbitrary contour point: drop it when it lies on a straight edge.
  if (dropClosingPoint(poly) && poly.size() >= 4 && Segment2{poly.back(), poly[1]}.distanceTo(poly[0]) <= tolerance_px)
    poly.erase(poly.begin());
  return poly;
}

}  // namespace

std::vector<Vec2> contourPolygon(const std::vector<Vec2>& contour, double tolerance_px, bool reference) {
  return contourPolygons(contour, tolerance_px, std::nullopt, reference).lines;
}

ContourPolygons contourPolygons(const std::vector<Vec2>& contour, double lines_tolerance_px,
                                std::optional<double> outline_tolerance_px, bool reference) {
  if (contour.empty()) return {};
  std::vector<Vec2> ring = contour;
  ring.push_back(contour.front());
  std::vector<double> tolerances{lines_tolerance_px};
  if (outline_tolerance_px) tolerances.push_back(*outline_tolerance_px);
  std::vector<std::vector<Vec2>> simplified;
  if (reference) {
    for (const double tolerance : tolerances) simplified.push_back(simplifyPolyline(ring, tolerance));
  } else {
    simplified = simplifyPixelChainAt(ring, tolerances);
  }
  ContourPolygons out;
  if (contour.size() >= 3) out.lines = ringPolygon(std::move(simplified[0]), lines_tolerance_px);
  if (outline_tolerance_px) {
    out.outline = std::move(simplified[1]);
    dropClosingPoint(out.outline);
  }
  return out;
}

std::vector<DetectedLine> fitLines(const std::vector<Vec2>& contour, const Camera& camera, const Image& valid,
                                   const LineOptions& options) {
  options.validate();
  return polygonLines(contourPolygon(contour, options.simplify_tolerance_px, options.reference), camera, valid,
                      options);
}

std::vector<DetectedLine> polygonLines(const std::vector<Vec2>& poly, const Camera& camera, const Image& valid,
                                       const LineOptions& options) {
  options.validate();
  std::vector<DetectedLine> lines;
  if (poly.size() < 2) return lines;

  // A point is near the frame edge when a pixel that does not see the ground (or lies outside)
  // is within frame_edge_px + 1 of it. Reference: the distance transform of the whole of `valid`;
  // fast: the pixels of the disk around each of the few points asked about (the same test).
  const double near_px = options.frame_edge_px + 1.0;
  const int w = valid.width, h = valid.height;
  cv::Mat dist;
  if (options.reference && !valid.empty()) {
    cv::Mat v(h, w, CV_8UC1, const_cast<std::uint8_t*>(valid.data.data()));
    cv::Mat padded;
    cv::copyMakeBorder(v != 0, padded, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(0));
    cv::distanceTransform(padded, dist, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  }
  const int reach = static_cast<int>(std::floor(near_px));
  const auto nearEdge = [&](const Vec2& p) -> bool {
    if (valid.empty()) return false;
    const int u = std::clamp(static_cast<int>(std::lround(p.x())), 0, w - 1);
    const int v = std::clamp(static_cast<int>(std::lround(p.y())), 0, h - 1);
    if (options.reference) return dist.at<float>(v + 1, u + 1) <= near_px;
    for (int dv = -reach; dv <= reach; ++dv) {
      for (int du = -reach; du <= reach; ++du) {
        if (std::sqrt(static_cast<float>(du * du + dv * dv)) > near_px) continue;
        const int x = u + du, y = v + dv;
        if (x < 0 || y < 0 || x >= w || y >= h || valid.data[static_cast<std::size_t>(y) * w + x] == 0) return true;
      }
    }
    return false;
  };

  const std::size_t n = poly.size();
  for (std::size_t i = 0; i < n; ++i) {
    DetectedLine line;
    line.image = {poly[i], poly[(i + 1) % n]};
    if (line.image.length() < options.min_length_px) continue;
    int near = 0;
    constexpr int kSamples = 11;
    for (int k = 0; k < kSamples; ++k) {
      if (nearEdge(line.image.pointAt(k / double(kSamples - 1)))) ++near;
    }
    line.frame_edge = near >= 9;
    const auto a = camera.backproject(line.image.a);
    const auto b = camera.backproject(line.image.b);
    if (a && b) line.vehicle = {*a, *b};
    lines.push_back(line);
  }
  return lines;
}

namespace {

// The sigma, m, of where the predicted line through `point` (vehicle frame) with unit normal `normal`
// lies across itself, under the pose covariance `cov` (x, y, heading in the vehicle frame): a pose
// error (dx, dy, dtheta) moves a point p of the world by -(dx - dtheta p.y, dy + dtheta p.x).
double acrossSigma(const Mat3& cov, const Vec2& point, const Vec2& normal) {
  const Vec3 j(normal.x(), normal.y(), normal.y() * point.x() - normal.x() * point.y());
  return std::sqrt(std::max(0.0, j.dot(cov * j)));
}

// Half the distance from `q`, a point of segment `s`, to the nearest other segment of `segments`
// within `max_angle` of s's direction whose extent lies beside q (q's foot on it within it):
// how far a gate at q may reach before it is nearer that segment; infinity when none is beside q.
double halfwayToNeighbour(const InterestSegment& s, const Vec2& q, const std::vector<InterestSegment>& segments,
                          double max_angle) {
  double nearest = std::numeric_limits<double>::infinity();
  for (const InterestSegment& other : segments) {
    if (&other == &s || other.vehicle.length() < 1e-6) continue;
    if (angleBetweenLines(s.vehicle, other.vehicle) > max_angle) continue;
    const Vec2 dir = other.vehicle.direction();
    const double t = (q - other.vehicle.a).dot(dir);
    if (t < 0 || t > other.vehicle.length()) continue;
    nearest = std::min(nearest, std::abs(other.vehicle.signedDistance(q)));
  }
  return 0.5 * nearest;
}

}  // namespace

void labelLines(std::vector<DetectedLine>& lines, const PredictedObject& prediction, const LineOptions& options) {
  options.validate();
  const double max_angle = options.max_angle_deg * std::numbers::pi / 180.0;
  const double gate_sigma = prediction.map_sigma_m > 0 ? options.gate_sigma_uncertain_map : options.gate_sigma;
  for (DetectedLine& line : lines) {
    line.label.reset();
    line.score = 0;
    if (line.frame_edge || line.vehicle.length() < 1e-6) continue;
    double best = 0;
    const InterestSegment* best_seg = nullptr;
    for (const InterestSegment& s : prediction.segments) {
      if (s.vehicle.length() < 1e-6) continue;
      const double angle = angleBetweenLines(line.vehicle, s.vehicle);
      if (angle > max_angle) continue;
      // Each end point against the gate at that point: the larger of max_distance_m and gate_sigma
      // times the predicted line's sigma there, the latter no further than halfway to the
      // neighbouring segment beside it. d, for the score: the worse end's distance in units of its
      // gate, times the floor (exactly the distance where the gate is the floor).
      const Vec2 normal(-s.vehicle.direction().y(), s.vehicle.direction().x());
      auto gate = [&](const Vec2& p) {
        if (gate_sigma <= 0) return options.max_distance_m;
        const double wide = gate_sigma * acrossSigma(prediction.pose_covariance, p, normal);
        if (wide <= options.max_distance_m) return options.max_distance_m;
        const Vec2 q = s.vehicle.closestPoint(p);
        return std::max(options.max_distance_m, std::min(wide, halfwayToNeighbour(s, q, prediction.segments, max_angle)));
      };
      const double ga = gate(line.vehicle.a), gb = gate(line.vehicle.b);
      const double da = std::abs(s.vehicle.signedDistance(line.vehicle.a));
      const double db = std::abs(s.vehicle.signedDistance(line.vehicle.b));
      if (da > ga || db > gb) continue;
      const double d = std::max(da * (options.max_distance_m / ga), db * (options.max_distance_m / gb));
      // Overlap of the line's projection onto the segment.
      const Vec2 dir = s.vehicle.direction();
      const double L = s.vehicle.length();
      double ta = (line.vehicle.a - s.vehicle.a).dot(dir), tb = (line.vehicle.b - s.vehicle.a).dot(dir);
      if (ta > tb) std::swap(ta, tb);
      const double len = std::max(tb - ta, 1e-9);
      const double overlap = std::max(0.0, std::min(tb, L) - std::max(ta, 0.0)) / std::min(len, L);
      if (overlap < options.min_overlap) continue;
      const double score = (1.0 - 0.5 * d / options.max_distance_m) * (1.0 - 0.5 * angle / max_angle) *
                           std::min(1.0, 0.5 + 0.5 * overlap);
      if (score > best) {
        best = score;
        best_seg = &s;
      }
    }
    if (best_seg != nullptr) {
      line.label = best_seg->id;
      line.score = best;
    }
  }
  // Relations: a labelled parallel pair must be about the predicted distance apart.
  std::map<std::string, std::vector<DetectedLine*>> by_label;
  for (DetectedLine& line : lines)
    if (line.label) by_label[*line.label].push_back(&line);
  for (const SegmentRelation& rel : prediction.relations) {
    if (rel.type != SegmentRelation::Type::Parallel) continue;
    const auto ia = by_label.find(rel.a), ib = by_label.find(rel.b);
    if (ia == by_label.end() || ib == by_label.end()) continue;
    for (DetectedLine* la : ia->second) {
      for (DetectedLine* lb : ib->second) {
        if (!la->label || !lb->label) continue;
        const Vec2 mid = 0.5 * (lb->vehicle.a + lb->vehicle.b);
        const double sep = std::abs(la->vehicle.signedDistance(mid));
        if (std::abs(sep - rel.separation_m) > options.relation_tolerance_m) {
          DetectedLine* worse = la->score < lb->score ? la : lb;
          worse->label.reset();
          worse->score = 0;
        }
      }
    }
  }
}

}  // namespace mapnav
