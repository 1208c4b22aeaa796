#include "mapnav/navigator/steering.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>

#include "mapnav/core/error.h"
#include "mapnav/core/options.h"

namespace mapnav {

namespace {

// The closest point must lie in the path's last metre for "past the end" to count.
constexpr double kArrivalReachM = 1.0;
// Lowest speed while slowing down for the end, m/s: slow enough to stop within a few centimetres.
constexpr double kCreepSpeedMps = 0.1;

bool arrived(const PathTracker& tracker, const Pose2& pose) {
  const Vec2& p = pose.translation();
  const PathTracker::Closest c = tracker.closest(p);
  if (tracker.endS() - c.s > kArrivalReachM) return false;
  const PathPoint& end = tracker.path().back();
  const Vec2 from_end = p - end.position;
  return from_end.norm() <= kArrivalToleranceM || from_end.dot(unitVector(end.heading)) >= 0.0;
}

// Cruise speed, lowered near the end so that braking at half the vehicle's deceleration stops it
// there: v = √(2 a d) for d metres left, never below the creep speed (nor above cruise).
double approachSpeed(double cruise, const VehicleLimits& limits, double remaining_m) {
  const double braking = 0.5 * limits.max_accel_mps2;
  const double creep = std::min(kCreepSpeedMps, cruise);
  const double v = std::min(cruise, std::max(creep, std::sqrt(2.0 * braking * std::max(0.0, remaining_m))));
  return std::clamp(v, limits.min_speed_mps, limits.max_speed_mps);
}

double clampTurnRate(double omega, const VehicleLimits& limits) {
  return std::clamp(omega, -limits.max_turn_rate_rad_s, limits.max_turn_rate_rad_s);
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// PathTracker

PathTracker::PathTracker(std::vector<PathPoint> path, double window_m) : path_(std::move(path)), window_m_(window_m) {
  requireArgument(std::isfinite(window_m) && window_m > 0, "PathTracker", "window_m", window_m, "finite and > 0");
  if (path_.size() < 2) throw InvalidInput("PathTracker: a path needs at least 2 points");
  for (std::size_t i = 0; i < path_.size(); ++i) {
    const PathPoint& p = path_[i];
    if (!std::isfinite(p.s) || !std::isfinite(p.heading) || !p.position.allFinite())
      throw InvalidInput("PathTracker: path point " + std::to_string(i) + " is not finite");
    if (i > 0 && p.s < path_[i - 1].s)
      throw InvalidInput("PathTracker: arc length decreases at path point " + std::to_string(i));
  }
  if (!(path_.back().s > path_.front().s)) throw InvalidInput("PathTracker: the path has zero length");
  reset();
}

void PathTracker::reset() {
  progress_ = path_.front().s;
  segment_ = 0;
  started_ = false;
}

PathTracker::Closest PathTracker::closest(const Vec2& position) const {
  Closest best;
  double best_distance = std::numeric_limits<double>::infinity();
  const double reach = started_ ? progress_ + window_m_ : std::numeric_limits<double>::infinity();
  for (std::size_t i = started_ ? segment_ : 0; i + 1 < path_.size(); ++i) {
    const PathPoint& a = path_[i];
    const PathPoint& b = path_[i + 1];
    if (a.s > reach) break;
    const double ds = b.s - a.s;
    if (ds <= 0) continue;  // repeated point
    const Vec2 d = b.position - a.position;
    const double len2 = d.squaredNorm();
    double t = len2 > 0 ? std::clamp((position - a.position).dot(d) / len2, 0.0, 1.0) : 0.0;
    if (started_ && i == segment_) t = std::max(t, std::clamp((progress_ - a.s) / ds, 0.0, 1.0));  // never back
    const Vec2 q = a.position + t * d;
    const double distance = (position - q).norm();
    if (distance < best_distance) {
      best_distance = distance;
      const Vec2 tangent = len2 > 0 ? Vec2(d) : unitVector(a.heading);
      best.s = a.s + t * ds;
      best.point = q;
      best.distance = distance;
      best.lateral = cross2(tangent, position - q) < 0 ? -distance : distance;
      best.segment = i;
    }
  }
  return best;
}

PathTracker::Closest PathTracker::update(const Vec2& position) {
  const Closest c = closest(position);
  progress_ = std::max(progress_, c.s);
  segment_ = c.segment;
  started_ = true;
  return c;
}

Vec2 PathTracker::pointAt(double s) const {
  if (s <= path_.front().s) return path_.front().position;
  if (s >= path_.back().s) return path_.back().position + (s - path_.back().s) * unitVector(path_.back().heading);
  const auto it = std::upper_bound(path_.begin(), path_.end(), s, [](double v, const PathPoint& p) { return v < p.s; });
  const PathPoint& b = *it;
  const PathPoint& a = *(it - 1);
  const double t = b.s > a.s ? (s - a.s) / (b.s - a.s) : 0.0;
  return a.position + t * (b.position - a.position);
}

// ---------------------------------------------------------------------------------------------
// PurePursuit

const OptionTable<PurePursuitOptions>& purePursuitOptionTable() {
  using O = PurePursuitOptions;
  static const OptionTable<O> table =
      OptionTable<O>("PurePursuitOptions")
          .field("lookahead_m", &O::lookahead_m, above(0),
                 "distance along the path, from the closest point, to the goal point, m")
          .field("speed_mps", &O::speed_mps, above(0), "cruise speed, m/s")
          .field("turn_in_place_deg", &O::turn_in_place_deg, aboveUpTo(0, 180),
                 "facing more than this away from the path's heading, the vehicle turns in place towards it, degrees")
          .field("turn_in_place_until_deg", &O::turn_in_place_until_deg,
                 "... until it faces within this of the path's heading, degrees")
          .check("turn_in_place_until_deg",
                 [](const O& o) {
                   return o.turn_in_place_until_deg > 0 && o.turn_in_place_until_deg < o.turn_in_place_deg;
                 },
                 "in (0, turn_in_place_deg)");
  return table;
}

void PurePursuitOptions::validate() const { purePursuitOptionTable().validate(*this); }

PurePursuit::PurePursuit(std::vector<PathPoint> path, PurePursuitOptions options, VehicleLimits limits)
    : tracker_(std::move(path)), options_(options), limits_(limits), goal_(tracker_.path().front().position) {
  options_.validate();
  limits_.validate();
}

VehicleCommand PurePursuit::command(const Pose2& pose) {
  const PathTracker::Closest c = tracker_.update(pose.translation());
  if (finished(pose)) return {};
  // Facing away from the path (a route that turns around): turn in place towards it first.
  const double away = facing(c, pose);
  if (std::abs(away) > degToRad(options_.turn_in_place_deg)) turning_in_place_ = true;
  if (std::abs(away) < degToRad(options_.turn_in_place_until_deg)) turning_in_place_ = false;
  if (turning_in_place_) {
    goal_ = c.point;
    return VehicleCommand{0.0, away >= 0 ? limits_.max_turn_rate_rad_s : -limits_.max_turn_rate_rad_s};
  }
  goal_ = tracker_.pointAt(c.s + options_.lookahead_m);
  const Vec2 g = pose.inverseTransform(goal_);
  const double d2 = g.squaredNorm();
  const double curvature = d2 > 1e-12 ? 2.0 * g.y() / d2 : 0.0;
  VehicleCommand out;
  out.speed_mps = approachSpeed(options_.speed_mps, limits_, tracker_.endS() - c.s);
  out.turn_rate_rad_s = clampTurnRate(out.speed_mps * curvature, limits_);
  return out;
}

bool PurePursuit::finished(const Pose2& pose) const { return arrived(tracker_, pose); }

double PurePursuit::facing(const PathTracker::Closest& closest, const Pose2& pose) const {
  return normalizeAngle(tracker_.path()[closest.segment].heading - pose.heading());
}

bool PurePursuit::turnsInPlaceAt(const Pose2& pose) const {
  return turning_in_place_ ||
         std::abs(facing(tracker_.closest(pose.translation()), pose)) > degToRad(options_.turn_in_place_deg);
}

double PurePursuit::crossTrackError(const Pose2& pose) const { return tracker_.closest(pose.translation()).lateral; }

// ---------------------------------------------------------------------------------------------
// CenterServo

const OptionTable<CenterServoOptions>& centerServoOptionTable() {
  using O = CenterServoOptions;
  static const OptionTable<O> table =
      OptionTable<O>("CenterServoOptions")
          .field("lookahead_m", &O::lookahead_m, above(0),
                 "distance along the path, from the closest point, to the road-centre point servoed on, m")
          .field("gain", &O::gain, above(0), "turn rate per pixel of x = u - cx, rad/s/px (CenterServo::matchedGain)")
          .field("speed_mps", &O::speed_mps, above(0), "cruise speed, m/s");
  return table;
}

void CenterServoOptions::validate() const { centerServoOptionTable().validate(*this); }

CenterServo::CenterServo(std::vector<PathPoint> path, const Camera& camera, CenterServoOptions options,
                         VehicleLimits limits)
    : tracker_(std::move(path)), camera_(&camera), options_(options), limits_(limits) {
  options_.validate();
  limits_.validate();
}

double CenterServo::matchedGain(const Camera& camera, double lookahead_m, double speed_mps) {
  requireArgument(std::isfinite(lookahead_m) && lookahead_m > 0, "CenterServo::matchedGain", "lookahead_m", lookahead_m,
                  "finite and > 0");
  requireArgument(std::isfinite(speed_mps) && speed_mps > 0, "CenterServo::matchedGain", "speed_mps", speed_mps,
                  "finite and > 0");
  const double dy = 1e-3 * lookahead_m;
  const std::optional<Vec2> left = camera.projectGround(Vec2(lookahead_m, dy));
  const std::optional<Vec2> right = camera.projectGround(Vec2(lookahead_m, -dy));
  if (!left || !right) throw InvalidInput("CenterServo::matchedGain: the camera cannot image the ground point " +
                                          std::to_string(lookahead_m) + " m ahead");
  const double du_dy = (left->x() - right->x()) / (2.0 * dy);  // pixels per metre left; negative
  if (!(du_dy < 0))
    throw InvalidInput("CenterServo::matchedGain: a point moving left does not move left in the image");
  return 2.0 * speed_mps / (lookahead_m * lookahead_m * -du_dy);
}

VehicleCommand CenterServo::command(const Pose2& pose) {
  const PathTracker::Closest c = tracker_.update(pose.translation());
  if (finished(pose)) return {};
  Observation obs;
  obs.target_vehicle = pose.inverseTransform(tracker_.pointAt(c.s + options_.lookahead_m));
  const std::optional<Vec2> pixel = camera_->projectGround(obs.target_vehicle);
  if (pixel && camera_->inImage(*pixel)) {
    obs.in_image = true;
    obs.pixel = *pixel;
    obs.x_px = pixel->x() - camera_->intrinsics().cx;
  } else {
    obs.x_px = -camera_->intrinsics().fx * std::atan2(obs.target_vehicle.y(), obs.target_vehicle.x());
  }
  observation_ = obs;
  VehicleCommand out;
  out.speed_mps = approachSpeed(options_.speed_mps, limits_, tracker_.endS() - c.s);
  out.turn_rate_rad_s = clampTurnRate(-options_.gain * obs.x_px, limits_);
  return out;
}

bool CenterServo::finished(const Pose2& pose) const { return arrived(tracker_, pose); }

double CenterServo::crossTrackError(const Pose2& pose) const { return tracker_.closest(pose.translation()).lateral; }

}  // namespace mapnav
