// The mapless tracking loop (mapnav/mission/track.h): the bootstrap prediction, the edges and the
// road region carried from frame to frame by the odometry, and the measurements on one image row.
#include "mapnav/mission/track.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "mapnav/core/error.h"
#include "mapnav/core/options.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/mission/image_region.h"

namespace mapnav {

namespace {

constexpr const char* kLeft = "track.left";
constexpr const char* kRight = "track.right";
/// Carried edges keep their near part: beyond this distance a trace near the horizon wanders.
constexpr double kCarryFarM = 25.0;

InterestSegment edgeSegment(const std::string& id, const Segment2& ground, const Camera& camera) {
  InterestSegment s;
  s.id = id;
  s.owner = "track";
  s.side = id == kLeft ? "left" : "right";
  s.vehicle = ground;
  const auto a = camera.projectGround(ground.a), b = camera.projectGround(ground.b);
  if (a && b) s.image = {*a, *b};
  return s;
}

/// The first frame's prediction: the trapezoid as the road region, its sides as the road's edges.
PredictedObject bootstrapPrediction(const Polygon2& trapezoid, const Camera& camera) {
  PredictedObject p = predictionFromImageRegion(trapezoid, camera).view;
  // bottomTrapezoid's corners: bottom left, bottom right, top right, top left.
  const auto bl = camera.backproject(trapezoid[0]), br = camera.backproject(trapezoid[1]);
  const auto tr = camera.backproject(trapezoid[2]), tl = camera.backproject(trapezoid[3]);
  if (bl && tl) p.segments.push_back(edgeSegment(kLeft, {*bl, *tl}, camera));
  if (br && tr) p.segments.push_back(edgeSegment(kRight, {*br, *tr}, camera));
  return p;
}

}  // namespace

Polygon2 laneOutline(const Camera& camera, double width_m, double far_m) {
  const auto bad = [](const std::string& why) { return InvalidInput("the lane: " + why); };
  if (!std::isfinite(width_m) || width_m <= 0 || !std::isfinite(far_m) || far_m <= 0)
    throw bad("its width and far end must be positive metres");
  const auto near = camera.backproject(Vec2((camera.width() - 1) / 2.0, 0.98 * camera.height()));
  if (!near) throw bad("the camera does not see the ground near the image's bottom row");
  if (far_m <= near->x())
    // The distance rounded up, so that the message never reads as a far end beyond it.
    throw bad("the far end " + numberText(far_m) + " m is not beyond the nearest ground in view, " +
              strprintf("%.2f", std::ceil(near->x() * 100) / 100) + " m ahead");
  // The image's left is the vehicle's left (+y).
  Polygon2 outline;
  for (const Vec2& g : {Vec2(near->x(), width_m / 2), Vec2(near->x(), -width_m / 2), Vec2(far_m, -width_m / 2),
                        Vec2(far_m, width_m / 2)}) {
    const auto p = camera.projectGround(g);
    if (!p) throw bad("a corner of the lane cannot be imaged by the camera");
    outline.push_back(*p);
  }
  return outline;
}

namespace {

/// The edges a detection found, on the ground, by the label the tracker gave them: from the nearest
/// point to the farthest within kCarryFarM.
std::map<std::string, Segment2> detectedEdges(const DetectedObject& d) {
  std::map<std::string, std::vector<Vec2>> points;
  for (const DetectedLine& l : d.lines) {
    if (!l.label || (*l.label != kLeft && *l.label != kRight)) continue;
    for (const Vec2& p : {l.vehicle.a, l.vehicle.b})
      if (p.allFinite() && p.x() > 0 && p.norm() <= kCarryFarM) points[*l.label].push_back(p);
  }
  std::map<std::string, Segment2> edges;
  for (auto& [label, pts] : points) {
    std::sort(pts.begin(), pts.end(), [](const Vec2& a, const Vec2& b) { return a.x() < b.x(); });
    if (pts.size() >= 2 && (pts.back() - pts.front()).norm() > 0.5) edges[label] = {pts.front(), pts.back()};
  }
  return edges;
}

/// Where the polygon's sides cross image row v: the leftmost and the rightmost crossing.
std::optional<std::pair<double, double>> rowExtent(const Polygon2& polygon, double v) {
  std::optional<std::pair<double, double>> extent;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[(i + 1) % polygon.size()];
    if ((a.y() - v) * (b.y() - v) > 0 || a.y() == b.y()) continue;
    const double u = a.x() + (b.x() - a.x()) * (v - a.y()) / (b.y() - a.y());
    if (!extent) extent = std::pair{u, u};
    extent->first = std::min(extent->first, u);
    extent->second = std::max(extent->second, u);
  }
  return extent;
}

/// Where the lines labelled `label` cross image row v (the first that does); nothing when none does.
std::optional<double> edgeColumn(const DetectedObject& d, const std::string& label, double v) {
  for (const DetectedLine& l : d.lines) {
    if (!l.label || *l.label != label) continue;
    const Vec2 &a = l.image.a, &b = l.image.b;
    if ((a.y() - v) * (b.y() - v) > 0 || a.y() == b.y()) continue;
    return a.x() + (b.x() - a.x()) * (v - a.y()) / (b.y() - a.y());
  }
  return std::nullopt;
}

/// The centre line's column on row v: its ground ends projected (a pin-hole images a ground line
/// as a straight line), the image line through them.
std::optional<double> centreColumn(const DetectedObject& d, const Camera& camera, double v) {
  if (!d.centerline_vehicle) return std::nullopt;
  const auto a = camera.projectGround(d.centerline_vehicle->a), b = camera.projectGround(d.centerline_vehicle->b);
  if (!a || !b || std::abs(b->y() - a->y()) < 1e-6) return std::nullopt;
  return a->x() + (b->x() - a->x()) * (v - a->y()) / (b->y() - a->y());
}

/// What one detection gives on row v: the region's sides (the edge lines where the pipeline labels
/// them, as the edge tracker does) and the centre line.
TrackedFrame measure(const DetectedObject& det, const Camera& camera, double v) {
  TrackedFrame r;
  r.ok = det.status == DetectedObject::Status::Ok;
  r.reason = det.reason;
  if (!r.ok) return r;
  if (const auto e = rowExtent(det.region_image, v)) {
    r.left_u = e->first;
    r.right_u = e->second;
  }
  if (const auto u = edgeColumn(det, kLeft, v)) r.left_u = u;
  if (const auto u = edgeColumn(det, kRight, v)) r.right_u = u;
  r.centre_u = centreColumn(det, camera, v);
  return r;
}

/// The edges and the road region the last frame found, in the current vehicle frame.
struct Carried {
  std::map<std::string, Segment2> edges;
  Polygon2 region;

  /// Moves them into the next vehicle frame: the odometry since the last frame as the new vehicle
  /// pose in the old vehicle frame (the mid-step heading model of PoseFilter::predict).
  void move(const LogFrame& f) {
    const Pose2 motion = stepPose(f.odometry);
    for (auto& entry : edges) entry.second = Segment2{motion.inverseTransform(entry.second.a), motion.inverseTransform(entry.second.b)};
    for (Vec2& p : region) p = motion.inverseTransform(p);
  }

  /// Each edge and the road region: where the last frame found it, else the bootstrap's.
  PredictedObject prediction(const PredictedObject& bootstrap, const Camera& camera, double t) const {
    PredictedObject p = bootstrap;
    for (InterestSegment& s : p.segments)
      if (const auto it = edges.find(s.id); it != edges.end()) s = edgeSegment(s.id, it->second, camera);
    if (region.size() >= 3) p.regions.front().vehicle = {region};
    p.timestamp = t;
    return p;
  }
};

}  // namespace

std::size_t TrackRun::tracked() const {
  return static_cast<std::size_t>(std::count_if(frames.begin(), frames.end(), [](const TrackedFrame& t) { return t.ok; }));
}

PathAgreementSummary TrackRun::pathAgreement() const {
  std::vector<PathAgreement> path;
  path.reserve(frames.size());
  for (const TrackedFrame& f : frames) path.push_back(f.path);
  return summarizePathAgreement(path, path_options);
}

std::optional<double> TrackRun::maxJump(std::optional<double> TrackedFrame::*member) const {
  std::optional<double> worst;
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const auto& a = frames[i - 1].*member;
    const auto& b = frames[i].*member;
    if (a && b) worst = std::max(worst.value_or(0.0), std::abs(*b - *a));
  }
  return worst;
}

const OptionTable<TrackOptions>& trackOptionTable() {
  using O = TrackOptions;
  static const OptionTable<O> table =
      OptionTable<O>("TrackOptions")
          .field("row", &O::row, atLeast(-1),
                 "the image row where the edges and the centre line are measured, pixels; -1: 85 % of the height")
          .field("max_frames", &O::max_frames, "run at most this many frames of the log; 0: every frame")
          .nest(&O::path, pathAgreementOptionTable())
          .check("row", [](const O& o) { return o.row == -1 || o.row >= 0; }, "-1 or >= 0");
  return table;
}

TrackRun trackLog(const ReplayLog& log, VisionPipeline& pipeline, const Camera& camera, const Polygon2& bootstrap,
                  const TrackOptions& options, const TrackObserver& observer) {
  trackOptionTable().validate(options);
  const int w = camera.width(), h = camera.height();
  TrackRun run;
  run.row = options.row >= 0 ? options.row : std::round(0.85 * (h - 1));
  // A rule between an option and the camera: no table can state it.
  requireArgument(run.row <= h - 1, "trackLog", "options.row", run.row,
                  "at most the camera image's last row, " + std::to_string(h - 1));
  run.path_options = options.path;
  const PredictedObject first = bootstrapPrediction(bootstrap, camera);
  const std::size_t total =
      options.max_frames > 0 ? std::min(options.max_frames, log.frames().size()) : log.frames().size();
  const TruthPoses truth = truthPoses(log.frames());  // every frame's, also beyond max_frames
  Carried carried;
  for (std::size_t i = 0; i < total; ++i) {
    const LogFrame& f = log.frames()[i];
    const Image rgb = toRgb(log.image(i));
    if (rgb.width != w || rgb.height != h)
      throw InvalidInput(f.image + ": the image is " + std::to_string(rgb.width) + "x" + std::to_string(rgb.height) +
                         " but the camera's is " + std::to_string(w) + "x" + std::to_string(h));
    carried.move(f);
    const PredictedObject prediction = carried.prediction(first, camera, f.t);
    const DetectedObject det = pipeline.detect(VisionFrame{w, h, rgb.data.data(), &camera, f.t}, prediction);
    run.frames.push_back(measure(det, camera, run.row));
    run.frames.back().path = pathAgreement(truth, i, det, camera, options.path);
    // An edge or a region not found in this frame is not carried on: a lost edge's last place drifts.
    carried.edges = detectedEdges(det);
    carried.region = run.frames.back().ok ? det.region_vehicle : Polygon2{};
    if (observer) observer(rgb, prediction, det, run.frames.back());
  }
  return run;
}

}  // namespace mapnav
