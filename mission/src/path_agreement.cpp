// Path agreement (mapnav/mission/path_agreement.h): the vehicle's future path from the log's truth,
// sampled by arc length, against the road region and the centre line a pipeline found.
#include "mapnav/mission/path_agreement.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "mapnav/geometry/polygon.h"
#include "mapnav/geometry/polyline2.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/mission/metrics.h"

namespace mapnav {

namespace {

/// Arc lengths within this of a bound count as on it (the samples are near + k · step).
constexpr double kArcSlack = 1e-9;

/// The arc length of sample k.
double sampleArc(const PathAgreementOptions& o, std::size_t k) { return o.near_m + static_cast<double>(k) * o.step_m; }

/// The least-squares line through the samples between direction_near_m and direction_far_m: its unit
/// direction, pointing from the nearer samples to the farther; nothing when the path stops short.
std::optional<Vec2> pathDirection(const std::vector<Vec2>& path, const PathAgreementOptions& o) {
  if (path.empty() || sampleArc(o, path.size() - 1) < o.direction_far_m - kArcSlack) return std::nullopt;
  std::vector<Vec2> pts;
  for (std::size_t k = 0; k < path.size(); ++k) {
    const double s = sampleArc(o, k);
    if (s >= o.direction_near_m - kArcSlack && s <= o.direction_far_m + kArcSlack) pts.push_back(path[k]);
  }
  if (pts.size() < 2) return std::nullopt;
  Vec2 mean;
  Vec2 dir = principalDirection(pts, mean);
  if (dir.dot(pts.back() - pts.front()) < 0) dir = -dir;
  return dir;
}

/// Where the polyline first reaches x = `x`: its y there; nothing when it does not.
std::optional<double> yAtX(const std::vector<Vec2>& path, double x) {
  for (std::size_t k = 0; k + 1 < path.size(); ++k) {
    const Vec2 &a = path[k], &b = path[k + 1];
    if ((a.x() - x) * (b.x() - x) > 0) continue;
    if (a.x() == b.x()) return a.y();
    return a.y() + (b.y() - a.y()) * (x - a.x()) / (b.x() - a.x());
  }
  if (path.size() == 1 && path.front().x() == x) return path.front().y();
  return std::nullopt;
}

/// The road found, as pathAgreement's comment defines it: true when the sample (ground point `g`,
/// pixel `px`) lies in it.
bool insideRoadFound(const DetectedObject& d, const Vec2& g, const Vec2& px) {
  if (d.region_image.size() >= 3) return contains(d.region_image, px);
  return contains(d.region_vehicle, g);
}

/// PathAgreement::ground_share: the lattice points below the horizon inside `region` / all of them.
std::optional<double> groundShare(const Polygon2& region, const Camera& camera) {
  constexpr int kLattice = 4;
  std::vector<Vec2> ground;
  for (int v = kLattice / 2; v < camera.height(); v += kLattice)
    for (int u = kLattice / 2; u < camera.width(); u += kLattice)
      if (camera.backproject(Vec2(u, v))) ground.emplace_back(u, v);
  if (ground.empty()) return std::nullopt;
  return static_cast<double>(countContained(region, ground)) / static_cast<double>(ground.size());
}

}  // namespace

const OptionTable<PathAgreementOptions>& pathAgreementOptionTable() {
  using O = PathAgreementOptions;
  static const OptionTable<O> table =
      OptionTable<O>("PathAgreementOptions")
          .field("near_m", &O::near_m, atLeast(0), "the first sample's arc length along the path from the vehicle, m")
          .field("far_m", &O::far_m, "the last sample's, m")
          .field("step_m", &O::step_m, above(0), "the samples' spacing in arc length, m")
          .field("min_reach_m", &O::min_reach_m, "a path that reaches less far than this is \"path too short\", m")
          .field("direction_near_m", &O::direction_near_m,
                 "the path's direction is the line fitted to its samples from this arc length, m ...")
          .field("direction_far_m", &O::direction_far_m, "... to this one, m")
          .field("offset_ahead_m", &O::offset_ahead_m, above(0),
                 "the lateral offset between the path and the centre line is measured at this x ahead, m")
          .field("inside_goal", &O::inside_goal, inRange(0, 1),
                 "a frame agrees when at least this fraction of its path in view lies inside the road found")
          .field("angle_goal_deg", &O::angle_goal_deg, inRange(0, 90),
                 "a centre line agrees when it is within this angle of the path's direction, degrees")
          .field("offset_jump_goal_m", &O::offset_jump_goal_m, atLeast(0),
                 "consecutive frames agree when their offsets differ by at most this, m")
          .check("far_m", [](const O& o) { return o.far_m > o.near_m; }, "> near_m")
          .check("min_reach_m", [](const O& o) { return o.min_reach_m >= o.near_m && o.min_reach_m <= o.far_m; },
                 "in [near_m, far_m]")
          .check("direction_near_m", [](const O& o) { return o.direction_near_m >= o.near_m; }, ">= near_m")
          .check("direction_far_m",
                 [](const O& o) { return o.direction_far_m > o.direction_near_m && o.direction_far_m <= o.far_m; },
                 "in (direction_near_m, far_m]");
  return table;
}

void PathAgreementOptions::validate() const { pathAgreementOptionTable().validate(*this); }

std::string_view toString(PathStatus status) {
  switch (status) {
    case PathStatus::Measured: return "measured";
    case PathStatus::NoTruth: return "no truth";
    case PathStatus::TooShort: return "path too short";
    case PathStatus::OutOfView: return "path out of view";
  }
  return "unknown";
}

TruthPoses truthPoses(const std::vector<LogFrame>& frames) {
  TruthPoses truth;
  truth.reserve(frames.size());
  for (const LogFrame& f : frames) truth.push_back(f.truth);
  return truth;
}

std::vector<Vec2> futurePath(const TruthPoses& truth, std::size_t i, const PathAgreementOptions& o) {
  if (i >= truth.size() || !truth[i]) return {};
  const Pose2& here = *truth[i];
  std::vector<Vec2> points{Vec2::Zero()};
  // The frames beyond far_m of arc length add nothing to the samples: stop there.
  double reach = 0;
  for (std::size_t j = i + 1; j < truth.size() && truth[j] && reach < o.far_m; ++j) {
    points.push_back(here.inverseTransform(truth[j]->translation()));
    reach += (points.back() - points[points.size() - 2]).norm();
  }
  const Polyline2 line(std::move(points));
  reach = line.length();
  if (reach < o.min_reach_m - kArcSlack) return {};
  const double end = std::min(o.far_m, reach);
  const auto n = static_cast<std::size_t>(std::floor((end - o.near_m) / o.step_m + kArcSlack)) + 1;
  std::vector<Vec2> path;
  path.reserve(n);
  for (std::size_t k = 0; k < n; ++k) path.push_back(line.pointAt(sampleArc(o, k)));
  return path;
}

std::vector<Vec2> futurePath(const std::vector<LogFrame>& frames, std::size_t i, const PathAgreementOptions& o) {
  return futurePath(truthPoses(frames), i, o);
}

DetectedObject roadFound(const DetectedObject& detection) {
  DetectedObject d;
  d.status = detection.status;
  d.region_image = detection.region_image;
  d.region_vehicle = detection.region_vehicle;
  d.centerline_vehicle = detection.centerline_vehicle;
  return d;
}

PathAgreement pathAgreement(std::vector<Vec2> path, const DetectedObject& detection, const Camera& camera,
                            const PathAgreementOptions& o) {
  PathAgreement r;
  r.path = std::move(path);
  if (r.path.empty()) {
    r.status = PathStatus::TooShort;
    return r;
  }
  const bool ok = detection.status == DetectedObject::Status::Ok;
  r.road_found = ok && (detection.region_image.size() >= 3 || detection.region_vehicle.size() >= 3);
  r.centre_line = ok && detection.centerline_vehicle.has_value();
  for (const Vec2& g : r.path) {
    const auto px = camera.projectGround(g);
    if (!px || !camera.inImage(*px)) {
      ++r.out_of_view;
      continue;
    }
    r.path_image.push_back(*px);
    if (r.road_found && insideRoadFound(detection, g, *px)) ++r.inside;
  }
  if (r.path_image.empty()) {
    r.status = PathStatus::OutOfView;
  } else {
    r.inside_fraction = static_cast<double>(r.inside) / static_cast<double>(r.path_image.size());
    if (!ok) r.ground_share = 0.0;
    else if (detection.region_image.size() >= 3) r.ground_share = groundShare(detection.region_image, camera);
  }
  r.path_direction = pathDirection(r.path, o);
  r.path_y_ahead = yAtX(r.path, o.offset_ahead_m);
  if (!r.centre_line) return r;
  const Segment2& c = *detection.centerline_vehicle;
  const Vec2 along = c.b - c.a;
  if (r.path_direction && along.norm() > 0)
    r.angle_deg = radToDeg(std::acos(std::clamp(std::abs(along.normalized().dot(*r.path_direction)), 0.0, 1.0)));
  if (r.path_y_ahead && std::abs(along.x()) > 1e-9) {
    const double centre_y = c.a.y() + along.y() * (o.offset_ahead_m - c.a.x()) / along.x();
    r.offset_m = *r.path_y_ahead - centre_y;
  }
  return r;
}

PathAgreement pathAgreement(const TruthPoses& truth, std::size_t i, const DetectedObject& detection,
                            const Camera& camera, const PathAgreementOptions& options) {
  PathAgreement r = pathAgreement(futurePath(truth, i, options), detection, camera, options);
  if (i < truth.size() && !truth[i]) r.status = PathStatus::NoTruth;
  return r;
}

PathAgreement pathAgreement(const std::vector<LogFrame>& frames, std::size_t i, const DetectedObject& detection,
                            const Camera& camera, const PathAgreementOptions& options) {
  return pathAgreement(truthPoses(frames), i, detection, camera, options);
}

std::optional<double> offsetJump(const std::vector<PathAgreement>& frames, std::size_t i) {
  if (i == 0 || i >= frames.size() || !frames[i - 1].offset_m || !frames[i].offset_m) return std::nullopt;
  return std::abs(*frames[i].offset_m - *frames[i - 1].offset_m);
}

namespace {

std::optional<double> fractionOf(std::size_t part, std::size_t whole) {
  if (whole == 0) return std::nullopt;
  return static_cast<double>(part) / static_cast<double>(whole);
}

std::optional<double> medianOf(const std::vector<double>& values) {
  if (values.empty()) return std::nullopt;
  return percentile(values, 50);
}

}  // namespace

PathAgreementSummary summarizePathAgreement(const std::vector<PathAgreement>& frames, const PathAgreementOptions& o) {
  PathAgreementSummary s;
  s.frames = frames.size();
  std::vector<double> insides, shares, angles, jumps;
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const PathAgreement& f = frames[i];
    s.centre_line_frames += f.centre_line;
    switch (f.status) {
      case PathStatus::NoTruth: ++s.no_truth; continue;
      case PathStatus::TooShort: ++s.path_too_short; continue;
      case PathStatus::OutOfView: ++s.out_of_view; continue;
      case PathStatus::Measured: break;
    }
    ++s.measured;
    s.no_region += !f.road_found;
    insides.push_back(f.inside_fraction.value_or(0.0));
    if (f.ground_share) shares.push_back(*f.ground_share);
    s.inside_goal_frames += insides.back() >= o.inside_goal;
    if (f.path_direction) {
      ++s.angle_frames;
      if (f.angle_deg) {
        angles.push_back(*f.angle_deg);
        s.angle_goal_frames += *f.angle_deg <= o.angle_goal_deg;
      } else {
        ++s.angle_missing;
      }
    }
    const PathAgreement* prev = i > 0 ? &frames[i - 1] : nullptr;
    if (!prev || prev->status != PathStatus::Measured || !prev->path_y_ahead || !f.path_y_ahead) continue;
    ++s.offset_pairs;
    if (const auto jump = offsetJump(frames, i)) {
      jumps.push_back(*jump);
      s.offset_goal_pairs += *jump <= o.offset_jump_goal_m;
    } else {
      ++s.offset_missing;
    }
  }
  s.median_inside = medianOf(insides);
  s.median_ground_share = medianOf(shares);
  s.inside_goal_fraction = fractionOf(s.inside_goal_frames, s.measured);
  s.median_angle_deg = medianOf(angles);
  s.median_offset_jump_m = medianOf(jumps);
  if (s.centre_line_frames > 0) {
    s.angle_goal_fraction = fractionOf(s.angle_goal_frames, s.angle_frames);
    s.offset_goal_fraction = fractionOf(s.offset_goal_pairs, s.offset_pairs);
  }
  return s;
}

}  // namespace mapnav
