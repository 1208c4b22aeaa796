// Line correspondences: labelled lines against the predicted chords or the map's edge polylines,
// and park mode's centre line against the nearest road's (correspondences.h).
#include "mapnav/localization/correspondences.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "mapnav/map/map.h"
#include "mapnav/map/predict.h"
#include "mapnav/tokens/detected_object.h"

namespace mapnav {

namespace {

/// Calls `use(line, predicted segment index)` for every detected line that is labelled with a
/// predicted segment, not cut by the frame, and at least `min_length_m` long.
template <typename Use>
void forEachLabelledLine(const Prediction& prediction, const DetectedObject& detected, double min_length_m, Use use) {
  if (detected.status != DetectedObject::Status::Ok) return;
  std::map<std::string, std::size_t, std::less<>> index;
  const std::size_t n = std::min(prediction.view.segments.size(), prediction.segments_world.size());
  for (std::size_t i = 0; i < n; ++i) index.emplace(prediction.view.segments[i].id, i);
  for (const DetectedLine& line : detected.lines) {
    if (!line.label || line.frame_edge || line.vehicle.length() < min_length_m) continue;
    const auto it = index.find(*line.label);
    if (it != index.end()) use(line, it->second);
  }
}

}  // namespace

std::vector<LineCorrespondence> labelledCorrespondences(const Prediction& prediction, const DetectedObject& detected,
                                                        double sigma_m, double min_length_m) {
  std::vector<LineCorrespondence> out;
  forEachLabelledLine(prediction, detected, min_length_m, [&](const DetectedLine& line, std::size_t i) {
    out.push_back({*line.label, line.vehicle, prediction.segments_world[i], sigma_m, {}});
  });
  return out;
}

std::vector<LineCorrespondence> edgeCorrespondences(const Map& map, const Prediction& prediction,
                                                    const DetectedObject& detected, const Pose2& prior,
                                                    double sigma_m, double min_length_m, double piece_m) {
  std::vector<LineCorrespondence> out;
  forEachLabelledLine(prediction, detected, min_length_m, [&](const DetectedLine& line, std::size_t i) {
    const InterestSegment& segment = prediction.view.segments[i];
    const Segment2& chord = prediction.segments_world[i];
    const Road* road = (segment.side == "left" || segment.side == "right") ? map.findRoad(segment.owner) : nullptr;
    const Polyline2* edge = road == nullptr ? nullptr : &(segment.side == "left" ? map.leftEdge(*road) : map.rightEdge(*road));
    if (edge == nullptr || edge->segmentCount() == 0 || !(piece_m > 0)) {
      out.push_back({*line.label, line.vehicle, chord, sigma_m, {}});
      return;
    }
    // The stretch of the edge the predicted segment covers: the edge does not go on inside the
    // paved areas the prediction cut it at (a crossing road, an intersection's mouth).
    const double sa = edge->project(chord.a).arc_length, sb = edge->project(chord.b).arc_length;
    const double lo = std::min(sa, sb) - 0.25, hi = std::max(sa, sb) + 0.25;
    const int pieces = std::max(1, static_cast<int>(std::ceil(line.vehicle.length() / piece_m)));
    const double sigma = sigma_m * std::sqrt(static_cast<double>(pieces));
    // Re-association candidates: the segments of that stretch.
    const Polyline2 stretch = edge->slice(lo, hi);
    std::vector<Segment2> candidates;
    for (std::size_t k = 0; k < stretch.segmentCount(); ++k) candidates.push_back(stretch.segment(k));
    for (int k = 0; k < pieces; ++k) {
      const Segment2 piece{line.vehicle.pointAt(static_cast<double>(k) / pieces),
                           line.vehicle.pointAt(static_cast<double>(k + 1) / pieces)};
      const Polyline2::Projection p = edge->project(prior.transform(piece.pointAt(0.5)));
      if (p.arc_length < lo || p.arc_length > hi) continue;
      out.push_back({*line.label, piece, edge->segment(p.segment), sigma, candidates});
    }
  });
  return out;
}

std::optional<LineCorrespondence> centerlineCorrespondence(const Map& map, const Pose2& prior,
                                                           const Segment2& centerline_vehicle, double sigma_m,
                                                           double search_radius_m) {
  constexpr double kMinKeep = 1.0;  // m of the detected line kept at least
  const Vec2 mid = prior.transform(centerline_vehicle.pointAt(0.5));
  const Road* best = nullptr;
  Polyline2::Projection best_projection;
  for (const Road* road : map.roadsNear(mid, search_radius_m)) {
    const Polyline2::Projection p = road->centerline.project(mid);
    if (p.distance <= search_radius_m && (best == nullptr || p.distance < best_projection.distance)) {
      best = road;
      best_projection = p;
    }
  }
  if (best == nullptr || best->centerline.segmentCount() == 0) return std::nullopt;
  // The detected centre line is straight; on a curve the road's centre line over the same stretch
  // is an arc. Matching it against the one map segment under its midpoint (a tangent there) put
  // its ends a sagitta off that line: on park_loop's curves the gate then rejected frame after
  // frame and the estimate drifted off the path on odometry alone. So: the map's chord between the
  // points the detected ends project to. And the straight model holds near the vehicle only (the
  // image rows, which the road finder weighs alike, are mostly near: half of them see 2 to 3.7 m
  // ahead with the Terregator camera), so the detected line is cut back from its far end until
  // that chord is within sigma_m of the arc; what deviation is left is added to sigma.
  const Polyline2& line = best->centerline;
  const bool a_near = centerline_vehicle.a.norm() <= centerline_vehicle.b.norm();
  const Vec2 near = a_near ? centerline_vehicle.a : centerline_vehicle.b;
  const Vec2 far = a_near ? centerline_vehicle.b : centerline_vehicle.a;
  const double length = (far - near).norm();
  if (length < 1e-9) {
    return LineCorrespondence{best->id + ".centerline", centerline_vehicle, line.segment(best_projection.segment),
                              sigma_m, {}};
  }
  const double sn = line.project(prior.transform(near)).arc_length;
  for (double keep = length;; keep = std::max(kMinKeep, keep - 0.25)) {
    const Vec2 end = near + (far - near) * (keep / length);
    const double se = line.project(prior.transform(end)).arc_length;
    if (std::abs(se - sn) < 0.5) {  // no stretch of road under it: the segment under its midpoint
      return LineCorrespondence{best->id + ".centerline", centerline_vehicle, line.segment(best_projection.segment),
                                sigma_m, {}};
    }
    const Segment2 chord{line.pointAt(sn), line.pointAt(se)};
    double sagitta = 0;
    const double lo = std::min(sn, se), hi = std::max(sn, se);
    const int steps = static_cast<int>(std::ceil((hi - lo) / 0.25));
    for (int k = 1; k < steps; ++k) {
      sagitta = std::max(sagitta, chord.distanceTo(line.pointAt(lo + (hi - lo) * k / steps)));
    }
    if (sagitta <= sigma_m || keep <= kMinKeep) {
      return LineCorrespondence{best->id + ".centerline", Segment2{near, end}, chord, std::hypot(sigma_m, sagitta), {}};
    }
  }
}

}  // namespace mapnav
