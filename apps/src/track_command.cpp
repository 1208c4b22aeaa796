#include "track_command.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <map>
#include <ostream>
#include <sstream>

#include "cli.h"
#include "command_support.h"
#include "detect_command.h"
#include "mapnav/core/error.h"
#include "mapnav/core/json.h"
#include "mapnav/image/png.h"
#include "mapnav/map/camera_io.h"
#include "mapnav/sim/replay_log.h"
#include "mapnav/vision/overlay.h"
#include "mapnav/vision_iface/pipeline.h"
#include "pipelines_command.h"

namespace mapnav::cli {

namespace fs = std::filesystem;

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

Json optionalNumber(const std::optional<double>& v) { return v ? Json(std::round(*v * 10) / 10) : Json(nullptr); }

std::string text(const std::optional<double>& v) {
  if (!v) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(1) << *v;
  return s.str();
}

/// The largest change between consecutive frames where both have a value.
std::optional<double> maxJump(const std::vector<TrackedFrame>& frames, std::optional<double> TrackedFrame::*member) {
  std::optional<double> worst;
  for (std::size_t i = 1; i < frames.size(); ++i) {
    const auto& a = frames[i - 1].*member;
    const auto& b = frames[i].*member;
    if (a && b) worst = std::max(worst.value_or(0.0), std::abs(*b - *a));
  }
  return worst;
}

}  // namespace

int runLogTrack(const LogTrackConfig& config, std::ostream& out, std::ostream& err) {
  return guarded(err, [&] {
    config.trapezoid.validate();
    loadPlugins(config.plugins);
    auto pipeline = createPipeline(config.pipeline, config.options_json);
    const ReplayLog log = ReplayLog::open(config.dir);
    const std::shared_ptr<const Camera> camera =
        config.camera.empty() ? log.header().camera : std::shared_ptr<const Camera>(loadCamera(config.camera));
    const int w = camera->width(), h = camera->height();
    const double row = config.row >= 0 ? config.row : std::round(0.85 * (h - 1));
    if (row > h - 1) throw InvalidInput("--row " + std::to_string(config.row) + ": beyond the image's " + std::to_string(h) + " rows");
    const Polygon2 trapezoid = bottomTrapezoid(w, h, config.trapezoid);
    const PredictedObject bootstrap = bootstrapPrediction(trapezoid, *camera);

    const std::size_t total =
        config.max_frames > 0 ? std::min(config.max_frames, log.frames().size()) : log.frames().size();
    std::vector<TrackedFrame> frames;
    std::vector<Image> overlays;
    // The edges and the road region the last frame found, moved into the current vehicle frame.
    std::map<std::string, Segment2> carried;
    Polygon2 carried_region;
    for (std::size_t i = 0; i < total; ++i) {
      const LogFrame& f = log.frames()[i];
      const Image rgb = toRgb(log.image(i));
      if (rgb.width != w || rgb.height != h)
        throw InvalidInput(f.image + ": the image is " + std::to_string(rgb.width) + "x" + std::to_string(rgb.height) +
                           " but the camera's is " + std::to_string(w) + "x" + std::to_string(h));
      // The odometry since the last frame as the new vehicle pose in the old vehicle frame (the
      // mid-step heading model of PoseFilter::predict).
      const double d = f.odometry.distance_m, dh = f.odometry.dheading_rad;
      const Pose2 motion(d * std::cos(0.5 * dh), d * std::sin(0.5 * dh), dh);
      for (auto& entry : carried) entry.second = Segment2{motion.inverseTransform(entry.second.a), motion.inverseTransform(entry.second.b)};
      for (Vec2& p : carried_region) p = motion.inverseTransform(p);
      // Each edge and the road region: where the last frame found it, else the bootstrap's.
      PredictedObject prediction = bootstrap;
      for (InterestSegment& s : prediction.segments)
        if (const auto it = carried.find(s.id); it != carried.end()) s = edgeSegment(s.id, it->second, *camera);
      if (carried_region.size() >= 3) prediction.regions.front().vehicle = {carried_region};
      prediction.timestamp = f.t;
      const DetectedObject det = pipeline->detect(VisionFrame{w, h, rgb.data.data(), camera.get(), f.t}, prediction);

      TrackedFrame r;
      r.ok = det.status == DetectedObject::Status::Ok;
      r.reason = det.reason;
      if (r.ok) {
        if (const auto e = rowExtent(det.region_image, row)) {
          r.left_u = e->first;
          r.right_u = e->second;
        }
        // The edge lines, where the pipeline reports them (the edge tracker), are the sides.
        if (const auto u = edgeColumn(det, kLeft, row)) r.left_u = u;
        if (const auto u = edgeColumn(det, kRight, row)) r.right_u = u;
        r.centre_u = centreColumn(det, *camera, row);
      }
      // An edge or a region not found in this frame is not carried on: a lost edge's last place drifts.
      carried = detectedEdges(det);
      carried_region = r.ok ? det.region_vehicle : Polygon2{};
      frames.push_back(r);
      if (!config.overlays.empty() || !config.contact_sheet.empty())
        overlays.push_back(drawDetection(rgb, prediction, det, *camera));
    }
    if (!config.overlays.empty()) {
      fs::create_directories(config.overlays);
      for (std::size_t i = 0; i < overlays.size(); ++i) {
        std::ostringstream name;
        name << std::setw(6) << std::setfill('0') << i << ".png";
        writePng(overlays[i], fs::path(config.overlays) / name.str());
      }
    }

    if (!config.contact_sheet.empty() && !overlays.empty()) {
      // Eight frames evenly spread from the first to the last, at half size, two a row.
      constexpr std::size_t kTiles = 8;
      std::vector<Image> tiles;
      std::vector<std::string> captions;
      const std::size_t n = std::min(kTiles, overlays.size());
      for (std::size_t k = 0; k < n; ++k) {
        const std::size_t i = n == 1 ? 0 : (k * (overlays.size() - 1) + (n - 1) / 2) / (n - 1);
        tiles.push_back(overlays[i]);
        captions.push_back(config.pipeline + ", frame " + std::to_string(i));
      }
      writePng(contactSheet(tiles, captions, 2, 0.5), config.contact_sheet);
    }

    const auto tracked = std::count_if(frames.begin(), frames.end(), [](const TrackedFrame& t) { return t.ok; });
    const auto jump_left = maxJump(frames, &TrackedFrame::left_u), jump_right = maxJump(frames, &TrackedFrame::right_u),
               jump_centre = maxJump(frames, &TrackedFrame::centre_u);
    if (config.json) {
      Json per_frame = Json::array();
      for (std::size_t i = 0; i < frames.size(); ++i)
        per_frame.push_back({{"frame", i},
                             {"ok", frames[i].ok},
                             {"reason", frames[i].ok ? Json(nullptr) : Json(frames[i].reason)},
                             {"left_u", optionalNumber(frames[i].left_u)},
                             {"right_u", optionalNumber(frames[i].right_u)},
                             {"centre_u", optionalNumber(frames[i].centre_u)}});
      const Json j = {{"log", config.dir},
                      {"pipeline", config.pipeline},
                      {"frames", frames.size()},
                      {"tracked", tracked},
                      {"row", row},
                      {"max_jump_px",
                       {{"left", optionalNumber(jump_left)}, {"right", optionalNumber(jump_right)},
                        {"centre", optionalNumber(jump_centre)}}},
                      {"per_frame", per_frame}};
      out << dumpJson(j);
    } else {
      out << "frame  left_u  right_u  centre_u   (row " << row << ")\n";
      for (std::size_t i = 0; i < frames.size(); ++i) {
        out << std::setw(5) << i << "  " << std::setw(6) << text(frames[i].left_u) << "  " << std::setw(7)
            << text(frames[i].right_u) << "  " << std::setw(8) << text(frames[i].centre_u);
        if (!frames[i].ok) out << "  failed: " << frames[i].reason;
        out << "\n";
      }
      out << config.pipeline << ": " << tracked << " of " << frames.size() << " frames tracked; largest frame-to-frame jump on row "
          << row << ": left " << text(jump_left) << " px, right " << text(jump_right) << " px, centre "
          << text(jump_centre) << " px\n";
      if (!config.overlays.empty()) out << "overlays in " << config.overlays << "\n";
      if (!config.contact_sheet.empty()) out << "contact sheet " << config.contact_sheet << "\n";
    }
    return static_cast<int>(kOk);
  });
}

}  // namespace mapnav::cli
