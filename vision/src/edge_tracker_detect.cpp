// The edge tracker's detection (Wallace et al. 1985, 3.1-3.2; see edge_tracker.h): a frame's two road
// edges traced from their start points, taken to the ground, checked against each other (parallel,
// the expected width) and turned into the DetectedObject, or one edge alone where the other is lost.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "edge_tracker_internal.h"
#include "mapnav/core/error.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/geometry/simplify.h"
#include "mapnav/image/image.h"
#include "mapnav/vision/edge_tracker.h"

namespace mapnav {

namespace {

/// Distance from p to the polyline, and whether the closest point is interior (not an end point).
double polylineDistance(const std::vector<Vec2>& line, const Vec2& p, bool& interior, Vec2& closest) {
  double best = std::numeric_limits<double>::infinity();
  interior = false;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const Segment2 s{line[i], line[i + 1]};
    const double t = s.closestParameter(p);
    const Vec2 c = s.pointAt(t);
    const double d = (c - p).norm();
    if (d < best) {
      best = d;
      closest = c;
      interior = !((i == 0 && t <= 1e-9) || (i + 2 == line.size() && t >= 1 - 1e-9));
    }
  }
  return best;
}

/// Traces the vehicle's left and right edges from `starts` into report.left and report.right, each
/// in its band's grey image (made once per band). starts.left and starts.right become the starts the
/// traces kept.
void traceEdges(const EdgeTracker& tracker, const VisionFrame& frame, EdgeStarts& starts, EdgeTrackReport& report) {
  const EdgeTrackerOptions& options = tracker.options();
  const int w = frame.width, h = frame.height;
  // The grey image in each band an edge needs (most frames: one). A grey camera's frame (R = G = B)
  // has no normalised colour (every pixel 85): there the edge is traced in the grey level.
  const bool colourless = isGreyFrame(frame.rgb, w, h);
  std::vector<std::pair<GreyBand, GreyImage>> greys;
  greys.reserve(4);  // one per GreyBand: references handed out stay valid
  auto traced = [&](GreyBand band) { return colourless && normalised(band) ? GreyBand::Luminance : band; };
  auto grey = [&](GreyBand band) -> const GreyImage& {
    for (const auto& [b, g] : greys)
      if (b == band) return g;
    greys.emplace_back(band, toGrey(frame.rgb, w, h, band));
    return greys.back().second;
  };
  auto traceIf = [&](bool predicted, const EdgeStart& st) {
    if (predicted) {
      const GreyBand band = traced(st.band);  // the band the edge is really traced in, as reported
      const bool gate = options.gate_luminance && st.band == GreyBand::Luminance && normalised(options.band);
      TrackedEdge e = tracker.trace(grey(band), st.point, st.direction, st.polarity, gate, st.search_lo_u, st.search_hi_u);
      e.band = band;
      return e;
    }
    TrackedEdge none;
    none.stop_reason = "not predicted in the image";
    return none;
  };
  // An edge lost within min_points of its start starts again from the next predicted segment up
  // the image: on a curve the edge enters at the image's side, where the window is half outside
  // and a shadow's edge on the shoulder can take the second point (park_loop frame 421, R4's gravel
  // edge); its next segment's near end lies a few pixels from the true edge.
  auto traceSide = [&](bool predicted, EdgeStart& st, const std::vector<EdgeStart>& next) {
    TrackedEdge e = traceIf(predicted, st);
    for (std::size_t i = 1; i < next.size() && static_cast<int>(e.image.size()) < options.min_points; ++i) {
      TrackedEdge again = traceIf(true, next[i]);
      if (again.image.size() <= e.image.size()) continue;
      e = std::move(again);
      st = next[i];
    }
    e.label = st.label;
    return e;
  };
  report.left = traceSide(starts.trace_left, starts.left, starts.left_next);
  report.right = traceSide(starts.trace_right, starts.right, starts.right_next);
}

/// Every edge point to the ground; the trace ends at the first one above the horizon or beyond
/// max_range_m (near the horizon a pixel spans metres of ground, and a wide lens sees the trace
/// run on into the far distance, where it would swing the fitted ground lines).
void toGround(TrackedEdge& e, const Camera& cam, double max_range_m) {
  for (std::size_t i = 0; i < e.image.size(); ++i) {
    const auto g = cam.backproject(e.image[i]);
    if (!g || g->norm() > max_range_m) {
      e.image.resize(i);
      e.matches.resize(i);
      e.stop_reason = "beyond max_range_m";
      e.reached_top = false;
      break;
    }
    e.ground.push_back(*g);
  }
}

bool tracked(const TrackedEdge& e, int min_points) {
  return static_cast<int>(e.image.size()) >= min_points && e.ground.size() >= 2;
}

/// The edge's lines for the DetectedObject, labelled with the predicted segment it started from.
void addLines(DetectedObject& d, const TrackedEdge& e, const Camera& cam) {
  const std::vector<Vec2> poly = e.image.size() > 2 ? simplifyPolyline(e.image, 1.5) : e.image;
  for (std::size_t i = 0; i + 1 < poly.size(); ++i) {
    const auto ga = cam.backproject(poly[i]), gb = cam.backproject(poly[i + 1]);
    d.lines.push_back(DetectedLine{.label = e.label,
                                   .score = e.label ? e.eval.score : 0,
                                   .image = {poly[i], poly[i + 1]},
                                   .vehicle = ga && gb ? Segment2{*ga, *gb} : Segment2{}});
  }
}

/// The expected width of the road: `given` (the options') when positive, else the prediction's
/// parallel relation of the two segments the edges started from (`lid`, `rid`), else a parallel
/// relation of one of them with a segment on the road's other side (a relation with a segment of its
/// own side is a few centimetres: two pieces of the same edge).
double expectedWidth(double given, const PredictedObject& prediction, const std::string& lid, const std::string& rid) {
  double width = given;
  if (width > 0) return width;
  for (const SegmentRelation& r : prediction.relations) {
    if (r.type != SegmentRelation::Type::Parallel) continue;
    if ((r.a == lid && r.b == rid) || (r.a == rid && r.b == lid)) {
      width = r.separation_m;
      break;
    }
  }
  auto sideOf = [&](const std::string& id) -> std::string {
    for (const InterestSegment& s : prediction.segments)
      if (s.id == id) return s.side;
    return "";
  };
  if (width <= 0)
    for (const SegmentRelation& r : prediction.relations)
      if (r.type == SegmentRelation::Type::Parallel && (r.a == lid || r.b == lid || r.a == rid || r.b == rid) &&
          sideOf(r.a) != sideOf(r.b)) {
        width = r.separation_m;
        break;
      }
  return width;
}

/// The ground check of two edges into `pc`: width samples from each edge's points to the other edge
/// (where the nearest point is interior; their mid-points into `mids`), their median and spread, the
/// angle between the edges' principal directions, and the width against the expected one. False,
/// `pc` untouched, when fewer than 2 samples: the edges do not overlap on the ground.
bool checkPair(const TrackedEdge& left, const TrackedEdge& right, const PredictedObject& prediction,
               const std::string& lid, const std::string& rid, const EdgeTrackerOptions& o, EdgePairCheck& pc,
               std::vector<Vec2>& mids) {
  std::vector<double> widths;
  for (int side = 0; side < 2; ++side) {
    const std::vector<Vec2>& a = side == 0 ? left.ground : right.ground;
    const std::vector<Vec2>& b = side == 0 ? right.ground : left.ground;
    for (const Vec2& p : a) {
      bool interior = false;
      Vec2 c;
      const double d = polylineDistance(b, p, interior, c);
      if (!interior) continue;
      widths.push_back(d);
      mids.push_back(0.5 * (p + c));
    }
  }
  if (widths.size() < 2) return false;
  pc.width_m = edgeMedian(widths);
  double var = 0;
  for (double x : widths) var += (x - pc.width_m) * (x - pc.width_m);
  pc.width_sd_m = std::sqrt(var / static_cast<double>(widths.size()));
  Vec2 ml, mr;
  const Vec2 dl = principalDirection(left.ground, ml), dr = principalDirection(right.ground, mr);
  pc.angle_deg = std::acos(std::clamp(std::abs(dl.dot(dr)), 0.0, 1.0)) / kDeg;
  pc.parallel_ok = pc.angle_deg <= o.parallel_tolerance_deg && pc.width_sd_m <= o.max_width_sd_m;
  pc.expected_width_m = expectedWidth(o.expected_width_m, prediction, lid, rid);
  pc.width_ok = pc.expected_width_m <= 0 || std::abs(pc.width_m - pc.expected_width_m) <= o.width_tolerance * pc.expected_width_m;
  return true;
}

/// The DetectedObject of two checked edges: their lines, the region between them, the centre line
/// (the width samples' mid-points `mids` fitted with a line) and the confidence (the edges' mean score
/// × how well the width fits the expected one).
DetectedObject twoEdges(const VisionFrame& frame, const EdgeTrackReport& report, const std::vector<Vec2>& mids) {
  const Camera& cam = *frame.camera;
  const EdgePairCheck& pc = report.pair;
  DetectedObject d;
  d.timestamp = frame.timestamp;
  for (const TrackedEdge* e : {&report.left, &report.right}) addLines(d, *e, cam);
  // Region between the edges: left bottom → top, then right top → bottom.
  for (const Vec2& p : report.left.image) d.region_image.push_back(p);
  for (auto it = report.right.image.rbegin(); it != report.right.image.rend(); ++it) d.region_image.push_back(*it);
  for (const Vec2& p : d.region_image)
    if (const auto g = cam.backproject(p)) d.region_vehicle.push_back(*g);
  // Centre line: the mid-points fitted with a line, from the nearest to the farthest.
  Vec2 mean;
  const Vec2 dir = principalDirection(mids, mean);
  double tmin = std::numeric_limits<double>::infinity(), tmax = -tmin;
  for (const Vec2& m : mids) {
    const double t = (m - mean).dot(dir);
    tmin = std::min(tmin, t);
    tmax = std::max(tmax, t);
  }
  d.centerline_vehicle = Segment2{mean + tmin * dir, mean + tmax * dir};
  const double width_fit =
      pc.expected_width_m > 0 ? 1 - std::abs(pc.width_m - pc.expected_width_m) / pc.expected_width_m : 1.0;
  d.confidence = std::clamp(0.5 * (report.left.eval.score + report.right.eval.score) * width_fit, 0.0, 1.0);
  return d;
}

/// The line fitted to an edge's image points (a straight edge on the ground is straight in a
/// pin-hole's image), and the points' spread about it (RMS, px, at least 1 px: how well the line
/// gives the edge's position).
struct ImageLine {
  Vec2 mean, direction;
  double spread = 1;
};

/// Nothing without an edge (a lost side) or with fewer than 2 points.
std::optional<ImageLine> fitImageLine(const TrackedEdge* e) {
  if (e == nullptr || e->image.size() < 2) return std::nullopt;
  ImageLine l;
  l.direction = principalDirection(e->image, l.mean);
  double ss = 0;
  for (const Vec2& p : e->image) {
    const Vec2 r = p - l.mean;
    const double off = r.x() * l.direction.y() - r.y() * l.direction.x();
    ss += off * off;
  }
  l.spread = std::max(1.0, std::sqrt(ss / static_cast<double>(e->image.size())));
  return l;
}

/// Column where the line crosses row v; `fallback` without a line or for a level one.
double boundaryColumn(const std::optional<ImageLine>& l, double v, double fallback) {
  if (!l || std::abs(l->direction.y()) < 1e-6) return fallback;
  return l->mean.x() + l->direction.x() * (v - l->mean.y()) / l->direction.y();
}

/// Whether an edge's ground points run within max_heading_deg of the vehicle's heading: a road edge
/// beside the vehicle does; a crossing marking, a shadow's or a car's lower edge need not.
bool alongHeading(const TrackedEdge& e, double max_heading_deg) {
  if (e.ground.size() < 2) return false;
  Vec2 mean;
  const Vec2 d = principalDirection(e.ground, mean);
  return std::abs(std::atan2(d.y(), d.x())) <= max_heading_deg * kDeg;
}

/// With starts from a predicted region: the road between the two edges (a lost edge's side: the
/// image's side), from the bottom row up to `top_v`, the edges extended beyond their traces; every
/// `row_step` rows, up to where the boundaries meet.
Polygon2 regionBetween(const std::optional<ImageLine>& left, const std::optional<ImageLine>& right, int w, int h,
                       double top_v) {
  Polygon2 l, r;
  const double row_step = 4;
  for (double v = h - 1.0; v >= top_v - 1e-9; v -= row_step) {
    const double ul = std::clamp(boundaryColumn(left, v, 0), 0.0, w - 1.0);
    const double ur = std::clamp(boundaryColumn(right, v, w - 1.0), 0.0, w - 1.0);
    if (ul >= ur) break;
    l.emplace_back(ul, v);
    r.emplace_back(ur, v);
  }
  Polygon2 ring = l;
  ring.insert(ring.end(), r.rbegin(), r.rend());
  return ring.size() >= 4 ? ring : Polygon2{};
}

/// The per-pixel road confidence of regionBetween's road: the least of three chances, each 1/2 on
/// the region's border. Inside each found edge: a logistic of the signed distance to its fitted line
/// in units of its points' spread about it (a lost edge's side: the image's side, certain). Nearer
/// than far_m: 1 / (1 + (range / far_m)^4), the far end's range being a guess good to a factor of
/// about 2 (0.94 at half of it, 0.06 at twice). 0 where the camera does not see the ground.
Image regionConfidence(const std::optional<ImageLine>& left, const std::optional<ImageLine>& right, const Camera& cam,
                       int w, int h, double far_m) {
  Image out(w, h, 1);
  const double sl = left ? left->spread : 1, sr = right ? right->spread : 1;
  auto logistic = [](double x) { return 1 / (1 + std::exp(-x)); };
  for (int v = 0; v < h; ++v) {
    const auto g = cam.backproject(Vec2(0.5 * (w - 1), v));
    if (!g) continue;
    const double pf = 1 / (1 + std::pow(g->norm() / far_m, 4));
    const double ul = boundaryColumn(left, v, -1e9), ur = boundaryColumn(right, v, 1e9);
    for (int u = 0; u < w; ++u) {
      const double p = std::min({pf, left ? logistic((u - ul) / sl) : 1.0, right ? logistic((ur - u) / sr) : 1.0});
      out.pixel(u, v)[0] = static_cast<std::uint8_t>(std::lround(255 * p));
    }
  }
  return out;
}

}  // namespace

DetectedObject EdgeTracker::regionDetection(const VisionFrame& frame, const std::string& why) const {
  const Camera& cam = *frame.camera;
  const bool left_ok = tracked(report_.left, options_.min_points) && alongHeading(report_.left, options_.max_heading_deg),
             right_ok = tracked(report_.right, options_.min_points) && alongHeading(report_.right, options_.max_heading_deg);
  const auto far = cam.projectGround(Vec2(options_.region_far_m, 0));
  const double top_v = std::clamp(far ? far->y() : 0.0, 0.0, frame.height - 1.0);
  DetectedObject d;
  d.timestamp = frame.timestamp;
  const std::optional<ImageLine> left = fitImageLine(left_ok ? &report_.left : nullptr),
                                 right = fitImageLine(right_ok ? &report_.right : nullptr);
  d.region_image = regionBetween(left, right, frame.width, frame.height, top_v);
  if (d.region_image.empty()) return DetectedObject::failed("edges cross: no road between them");
  for (const Vec2& p : d.region_image)
    if (const auto g = cam.backproject(p)) d.region_vehicle.push_back(*g);
  if (frame.want_masks)
    d.road_confidence = regionConfidence(left, right, cam, frame.width, frame.height, options_.region_far_m);
  if (left_ok) addLines(d, report_.left, cam);
  if (right_ok) addLines(d, report_.right, cam);
  const double score = (left_ok ? report_.left.eval.score : 0) + (right_ok ? report_.right.eval.score : 0);
  d.confidence = std::clamp(0.5 * score, 0.0, 1.0);
  d.reason = why;
  return d;
}

DetectedObject EdgeTracker::detect(const VisionFrame& frame, const PredictedObject& prediction) {
  if (frame.camera == nullptr) throw InvalidInput("pipeline \"edge-tracker\": the frame has no camera");
  if (frame.rgb == nullptr || frame.width <= 0 || frame.height <= 0)
    throw InvalidInput("pipeline \"edge-tracker\": the frame has no pixels");
  const Camera& cam = *frame.camera;
  const int w = frame.width, h = frame.height;
  report_ = {};
  last_left_.reset();
  last_right_.reset();
  auto fail = [&](const std::string& why) {
    DetectedObject d = DetectedObject::failed(why);
    d.timestamp = frame.timestamp;
    return d;
  };

  std::optional<EdgeStart> from_left, from_right;  // the carried edges' starts (both carried, or neither)
  if (options_.use_carried_edges && carried_left_ && carried_right_) {
    from_left = startFromCarried(carried_left_->ground, carried_left_->label, cam, w, h);
    from_right = startFromCarried(carried_right_->ground, carried_right_->label, cam, w, h);
  }
  EdgeStarts starts = chooseStarts(prediction, cam, w, h, options_, from_left, from_right);
  report_.start_source = starts.source;
  carried_left_.reset();
  carried_right_.reset();
  traceEdges(*this, frame, starts, report_);
  // The predicted segments the edges started from, for the expected width (prediction's relations).
  const bool predicted = report_.start_source == "prediction";
  const std::string lid = predicted && starts.trace_left ? starts.left.label.value_or("") : "";
  const std::string rid = predicted && starts.trace_right ? starts.right.label.value_or("") : "";
  for (TrackedEdge* e : {&report_.left, &report_.right}) toGround(*e, cam, options_.max_range_m);

  const bool left_ok = tracked(report_.left, options_.min_points), right_ok = tracked(report_.right, options_.min_points);
  if (report_.start_source == "region") {
    // The region's sides are no edges' positions: no pair check; a side without a step is road to
    // the image's side (see region_far_m).
    std::string why;
    if (!left_ok) why += "left edge lost: " + report_.left.stop_reason + "; ";
    if (!right_ok) why += "right edge lost: " + report_.right.stop_reason + "; ";
    if (!why.empty()) why += "the road taken to the image's side there";
    return regionDetection(frame, why);
  }
  if (!left_ok && !right_ok) {
    return fail("both edges lost: left: " + report_.left.stop_reason + "; right: " + report_.right.stop_reason);
  }
  if (!left_ok || !right_ok) {
    const std::string lost = !left_ok ? "left edge lost: " + report_.left.stop_reason
                                      : "right edge lost: " + report_.right.stop_reason;
    const TrackedEdge& good = left_ok ? report_.left : report_.right;
    if (!options_.single_edge || !good.label) return fail(lost);
    // One edge: lateral position and heading for the Map (its gate against the prediction is the
    // only check left), no centre line, half the confidence.
    (left_ok ? last_left_ : last_right_) = Carried{good.ground, good.label};
    DetectedObject d;
    d.timestamp = frame.timestamp;
    addLines(d, good, cam);
    d.confidence = std::clamp(0.5 * good.eval.score, 0.0, 1.0);
    d.reason = lost + "; the other edge alone";
    return d;
  }

  // Ground check: width samples from each edge to the other, parallelism of the fitted lines.
  std::vector<Vec2> mids;
  if (!checkPair(report_.left, report_.right, prediction, lid, rid, options_, report_.pair, mids))
    return fail("edges inconsistent: they do not overlap on the ground");
  last_left_ = Carried{report_.left.ground, report_.left.label};
  last_right_ = Carried{report_.right.ground, report_.right.label};
  const EdgePairCheck& pc = report_.pair;
  if (!pc.parallel_ok) {
    std::ostringstream s;
    s << "edges not parallel: " << pc.angle_deg << " deg apart, width spread " << pc.width_sd_m << " m";
    return fail(s.str());
  }
  if (!pc.width_ok) {
    std::ostringstream s;
    s << "edges inconsistent: width " << pc.width_m << " m, expected " << pc.expected_width_m << " m";
    return fail(s.str());
  }
  return twoEdges(frame, report_, mids);
}

}  // namespace mapnav
