#pragma once
// Motion Control's steering laws: path followers that turn a pose into a VehicleCommand.
//
//  * PurePursuit — the textbook geometric follower (Coulter 1992): the arc through a goal point a
//    lookahead distance along the path.
//  * CenterServo — the paper's servo (Wallace 1985, 3.6, step 8): "steer the vehicle to keep the
//    center of the road centered in the image", dτ/dt = γ · x, with x the image-plane abscissa of
//    the road-centre point a fixed distance ahead. Here the road centre comes from the path (the
//    map's centre line seen from the estimated pose) and the camera model gives its pixel.
//
// Both track their progress along the path with a PathTracker, so that a path that comes back near
// itself does not make them jump ahead, and both slow down to stop at the path's end.
#include <cstddef>
#include <vector>

#include "mapnav/core/option_table.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/navigator/path.h"
#include "mapnav/navigator/vehicle.h"

namespace mapnav {

/// Monotonic progress along a dense path (densePath's output): the closest point is searched only
/// forward of the last one, within a window of arc length.
class PathTracker {
 public:
  /// The closest point of the path to a position.
  struct Closest {
    double s = 0;               ///< arc length of the closest point, ≥ the progress before the search
    Vec2 point = Vec2::Zero();  ///< the closest point (on the segment between two path points)
    double lateral = 0;         ///< signed distance of the position, left of the path positive, m
    double distance = 0;        ///< |position − point|, m
    std::size_t segment = 0;    ///< index i of the segment path[i] → path[i + 1]
  };

  /// The search window: more than the vehicle drives between two commands (3 m: the paper's 3 s
  /// servo loop at 1 m/s), less than any stretch after which the path comes back near itself.
  static constexpr double kDefaultWindowM = 3.0;

  /// Throws InvalidInput for fewer than 2 points, arc lengths that decrease or are not finite, or a
  /// window that is not > 0.
  explicit PathTracker(std::vector<PathPoint> path, double window_m = kDefaultWindowM);

  /// The closest point to `position` among the segments from the current progress up to `window_m`
  /// further along; before the first update(), on the whole path, so the vehicle may start anywhere
  /// along it (for a path that comes back near itself, start nearer to the intended part than to
  /// any other: ties go to the smaller arc length). Does not move the progress.
  Closest closest(const Vec2& position) const;
  /// closest(), then moves the progress to its arc length (never backwards).
  Closest update(const Vec2& position);
  /// Back to the state before the first update().
  void reset();

  /// The point at arc length s: interpolated between path points, the first point for s < 0, and
  /// beyond the end the last point continued straight along the last heading.
  Vec2 pointAt(double s) const;
  double length() const { return path_.back().s - path_.front().s; }
  double startS() const { return path_.front().s; }
  double endS() const { return path_.back().s; }
  /// Arc length reached so far (the path's first s before any update()).
  double progress() const { return progress_; }
  const std::vector<PathPoint>& path() const { return path_; }

 private:
  std::vector<PathPoint> path_;
  double window_m_;
  double progress_ = 0;
  std::size_t segment_ = 0;  // segment holding progress_
  bool started_ = false;     // false: the next search covers the whole path
};

/// When a follower has arrived: within `kArrivalToleranceM` of the path's last point, or past it
/// (beyond the line through the end, perpendicular to the last heading), with the closest point in
/// the last metre of the path (so that a path ending near its start is not finished at the start).
inline constexpr double kArrivalToleranceM = 0.1;

struct PurePursuitOptions {
  /// Distance along the path, from the closest point, to the goal point, m (> 0). Shorter tracks
  /// tighter but reacts harder to noise in the pose; 1.5 m keeps the cross-track error under 3 cm
  /// on 15–25 m radius curves, S-bends included, and settles a 0.5 m offset within 0.1 m in about
  /// 2 m (steering_test.cpp).
  double lookahead_m = 1.5;
  /// Cruise speed, m/s (> 0). 0.6 m/s: twice the paper's 1.08 km/h, a slow walk.
  double speed_mps = 0.6;
  /// A vehicle facing more than this away from the path's heading at its closest point turns in
  /// place towards it (speed 0, the limits' turn rate), deg, in (0, 180]. The skid-steer vehicle
  /// turns on its tracks (vehicle.h); following a path that starts behind it by an arc would sweep a
  /// circle of radius speed / turn rate (1 m at 0.6 m/s), wider than a sidewalk: a route that turns
  /// around (an out-and-back via point) turns around in place.
  double turn_in_place_deg = 90.0;
  /// ... until it faces within this of the path's heading, deg, in (0, turn_in_place_deg): then pure
  /// pursuit takes over (10 deg: a 1.5 m lookahead then cuts in by under 0.1 m).
  double turn_in_place_until_deg = 10.0;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// The options' names, rules and descriptions; validate() checks them.
const OptionTable<PurePursuitOptions>& purePursuitOptionTable();

/// Pure pursuit: the goal point lies `lookahead_m` along the path from the closest point (beyond
/// the end, on the end's straight continuation); in the vehicle frame at (x, y), at distance
/// d = √(x² + y²), the arc through it has curvature κ = 2 y / d², and the turn rate is speed · κ,
/// clamped to the limits. (With d the actual distance to the goal, a vehicle on a circular path
/// stays on it exactly.) The speed is the cruise speed, lowered near the end to
/// √(2 · a · remaining) with a = max_accel_mps2 / 2 (never below 0.1 m/s, so it arrives). Facing
/// more than turn_in_place_deg away from the path, it turns in place (PurePursuitOptions).
class PurePursuit {
 public:
  /// Throws InvalidInput for invalid options or limits, or a path of fewer than 2 points.
  PurePursuit(std::vector<PathPoint> path, PurePursuitOptions options = {}, VehicleLimits limits = {});

  /// The command for the vehicle at `pose` (world frame); moves the progress along the path.
  /// Zero speed and turn rate once finished(pose).
  VehicleCommand command(const Pose2& pose);
  /// At the end: within 0.1 m of the path's last point or past it (see kArrivalToleranceM).
  bool finished(const Pose2& pose) const;
  /// Signed distance from the path (left positive), to the closest point forward of the progress.
  double crossTrackError(const Pose2& pose) const;

  /// The last goal point, world frame (the path's start before the first command).
  const Vec2& goal() const { return goal_; }
  const PathTracker& tracker() const { return tracker_; }
  const PurePursuitOptions& options() const { return options_; }
  /// Turning in place (facing away from the path): until within turn_in_place_until_deg of it.
  bool turningInPlace() const { return turning_in_place_; }
  /// Whether command(pose) would turn in place (turning already, or facing more than
  /// turn_in_place_deg away from the path there).
  bool turnsInPlaceAt(const Pose2& pose) const;
  /// Carries a turn in place on into a follower of a newer plan (Motion Control replaces its
  /// follower at every command; the turn must not stop at turn_in_place_deg).
  void continueTurningInPlace(bool turning) { turning_in_place_ = turning; }

 private:
  PathTracker tracker_;
  PurePursuitOptions options_;
  VehicleLimits limits_;
  Vec2 goal_;
  bool turning_in_place_ = false;

  // The path's heading at the closest point to `pose` (forward of the progress) − the pose's, (-pi, pi].
  double facing(const PathTracker::Closest& closest, const Pose2& pose) const;
};

struct CenterServoOptions {
  /// Distance along the path, from the closest point, to the road-centre point servoed on, m (> 0).
  /// It must be in the camera's view: the Terregator pin-hole (tilt 22°, f = 904 px) sees the
  /// ground from 2.0 m to 12.0 m ahead, 1.37 m wide at 2 m, 1.63 m at 2.5 m. Like pure pursuit the
  /// servo starts turning for a curve when the point reaches it, so it cuts into curves by about
  /// 0.011 · L² m where the curvature jumps from a 25 m right to a 15 m left radius: 0.175 m at 4 m
  /// (too much for a sidewalk; the 0.1 m bound needs L < 3 m), 0.069 m at 2.5 m, measured in
  /// steering_test.cpp. The speed does not change this (kinematic vehicle, matched gain). 2.5 m is
  /// near the bottom of the image (row 382 of 480), leaves ±0.8 m either side in view, and after a
  /// 0.5 m offset the vehicle is back within 0.1 m in under 4 m.
  double lookahead_m = 2.5;
  /// γ, turn rate per pixel of x = u − cx, rad/s/px (> 0): dτ/dt = −γ · x (the image's x grows to
  /// the right, turn rates to the left). The default is CenterServo::matchedGain for the default
  /// lookahead and speed and the Terregator pin-hole (maps/cameras/terregator_pinhole.json):
  /// γ = 2 v (L cos β + h sin β) / (f L²) = 2 · 0.6 · 2.880 / (904 · 2.5²) = 6.117e-4 rad/s/px
  /// (0.035 °/s per pixel), so that near the image centre the servo turns as pure pursuit with the
  /// same lookahead: a 1 m lateral offset 2.5 m ahead (314 px) gives 0.192 rad/s, the arc of
  /// radius 3.1 m through that point; 0.1 m gives 0.019 rad/s, a 31 m radius. The paper: "γ is a
  /// gain constant related to the distance ahead imaged and to vehicle speed" — change it with
  /// them (matchedGain), or the servo under- or over-steers.
  double gain = 6.117e-4;
  /// Cruise speed, m/s (> 0).
  double speed_mps = 0.6;

  /// Throws InvalidInput naming the first bad field and its value.
  void validate() const;
};

/// The options' names, rules and descriptions; validate() checks them.
const OptionTable<CenterServoOptions>& centerServoOptionTable();

/// The paper's servo. Each command: the road-centre point `lookahead_m` along the path from the
/// closest point is taken into the vehicle frame and projected with the camera; x = u − cx (pixels,
/// right positive) and the turn rate is −γ · x, clamped to the limits. A point the camera cannot
/// project, or whose pixel is outside the image, falls back to its vehicle-frame bearing
/// b = atan2(y, x) as the pixel offset of an ideal forward-looking camera, x ≈ −fx · b: the turn
/// rate is γ · fx · b (within a few % of the image law near the lookahead, and it still turns the
/// right way for a point far to the side or behind). Speed as PurePursuit's (cruise, slowing to
/// stop at the end).
class CenterServo {
 public:
  /// What the camera saw in the last command.
  struct Observation {
    Vec2 target_vehicle = Vec2::Zero();  ///< the road-centre point, vehicle frame, m
    Vec2 pixel = Vec2::Zero();           ///< its pixel, when in_image
    bool in_image = false;               ///< false: the bearing fallback was used
    double x_px = 0;                     ///< u − cx, or the fallback's −fx · bearing
  };

  /// `camera` is held by pointer: it must outlive the servo (and not move). Throws InvalidInput for
  /// invalid options or limits, or a path of fewer than 2 points.
  CenterServo(std::vector<PathPoint> path, const Camera& camera, CenterServoOptions options = {},
              VehicleLimits limits = {});

  /// The command for the vehicle at `pose` (world frame); moves the progress along the path.
  /// Zero speed and turn rate once finished(pose).
  VehicleCommand command(const Pose2& pose);
  bool finished(const Pose2& pose) const;  ///< as PurePursuit::finished
  double crossTrackError(const Pose2& pose) const;  ///< as PurePursuit::crossTrackError

  const Observation& lastObservation() const { return observation_; }
  const PathTracker& tracker() const { return tracker_; }
  const CenterServoOptions& options() const { return options_; }

  /// The γ that makes the servo turn as pure pursuit with lookahead L at speed v for a point
  /// straight ahead: −γ · ∂x/∂y = 2 v / L² at the ground point (L, 0) (∂x/∂y measured on the camera
  /// model, so any lens works). Throws InvalidInput when the camera cannot image that point or the
  /// arguments are not > 0.
  static double matchedGain(const Camera& camera, double lookahead_m, double speed_mps);

 private:
  PathTracker tracker_;
  const Camera* camera_;
  CenterServoOptions options_;
  VehicleLimits limits_;
  Observation observation_;
};

}  // namespace mapnav
