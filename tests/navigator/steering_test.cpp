// Motion Control: the skid-steer vehicle model, dense paths, pure pursuit and the paper's γ·x servo.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "mapnav/core/error.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/geometry/polyline2.h"
#include "mapnav/navigator/path.h"
#include "mapnav/navigator/steering.h"
#include "mapnav/navigator/vehicle.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

constexpr double kDt = 0.05;

// ---------------------------------------------------------------------------------------------
// Fixtures

// A route built from straight parts and circular arcs, sampled every 0.25 m along the arcs.
class RouteBuilder {
 public:
  RouteBuilder(Vec2 start, double heading) : p_(start), heading_(heading) { points_.push_back(start); }
  RouteBuilder& straight(double length) {
    p_ += length * unitVector(heading_);
    points_.push_back(p_);
    return *this;
  }
  // Positive angle turns left.
  RouteBuilder& arc(double radius, double angle_deg) {
    const double angle = degToRad(angle_deg);
    const double side = angle > 0 ? 1.0 : -1.0;
    const Vec2 centre = p_ + side * radius * leftNormal(unitVector(heading_));
    const int pieces = static_cast<int>(std::ceil(radius * std::abs(angle) / 0.25));
    const double h0 = heading_;
    for (int k = 1; k <= pieces; ++k) {
      const double h = h0 + angle * k / pieces;
      // The point at heading h on the circle: centre minus the left normal (times side).
      points_.push_back(centre - side * radius * leftNormal(unitVector(h)));
    }
    heading_ = h0 + angle;
    p_ = points_.back();
    return *this;
  }
  Polyline2 build() const { return Polyline2(points_); }

 private:
  Vec2 p_;
  double heading_;
  std::vector<Vec2> points_;
};

// ≈ 93 m: straight, a left R15, straight, a long right R25 running straight into a left R15 (an
// S-bend, curvature jumping by 1/25 + 1/15), straight.
Polyline2 curvyRoute() {
  return RouteBuilder(Vec2(0, 0), 0.0)
      .straight(10)
      .arc(15, 60)
      .straight(6)
      .arc(25, -90)
      .arc(15, 45)
      .straight(10)
      .build();
}


struct RunResult {
  double max_error = 0;              // max |cross-track error| over the whole run, m
  double max_error_after_10m = 0;    // ... once 10 m have been driven
  double end_distance = 0;           // from the stopped vehicle to the path's end, m
  bool finished = false;
  double driven = 0;                 // odometer, m
  double settled_after = 0;          // odometer when the error was last above 0.1 m, m
  int fallbacks = 0;                 // CenterServo: commands that used the bearing fallback
};

// Drives a SkidSteerVehicle from `start` (at rest) with `follower` until it is finished, then lets it
// stop. The cross-track error is measured on the route polyline itself (its global closest point),
// independently of the follower's tracker.
template <typename Follower>
RunResult drive(Follower& follower, const Polyline2& route, const Pose2& start) {
  SkidSteerVehicle vehicle(start);
  RunResult r;
  auto measure = [&] {
    const double e = route.project(vehicle.pose().translation()).distance;
    r.max_error = std::max(r.max_error, e);
    if (vehicle.odometer() >= 10.0) r.max_error_after_10m = std::max(r.max_error_after_10m, e);
    if (e > 0.1) r.settled_after = vehicle.odometer();
  };
  measure();
  const int max_steps = static_cast<int>(3.0 * route.length() / 0.6 / kDt);
  for (int i = 0; i < max_steps && !follower.finished(vehicle.pose()); ++i) {
    vehicle.step(follower.command(vehicle.pose()), kDt);
    if constexpr (requires { follower.lastObservation().in_image; }) {
      if (!follower.lastObservation().in_image) ++r.fallbacks;
    }
    measure();
  }
  r.finished = follower.finished(vehicle.pose());
  for (int i = 0; i < 100 && vehicle.speed() > 0; ++i) {
    vehicle.step(follower.command(vehicle.pose()), kDt);
    measure();
  }
  r.end_distance = (vehicle.pose().translation() - route.back()).norm();
  r.driven = vehicle.odometer();
  return r;
}

void report(const std::string& what, const RunResult& r) {
  std::cout << what << ": max cross-track " << r.max_error << " m, after 10 m " << r.max_error_after_10m
            << " m, within 0.1 m after " << r.settled_after << " m, end " << r.end_distance << " m, driven "
            << r.driven << " m, " << r.fallbacks << " bearing fallbacks\n";
}

// The start 0.5 m left (or right) of the route's start, heading along it.
Pose2 offsetStart(const Polyline2& route, double lateral) {
  const double h = route.headingAt(0);
  return Pose2(route.front() + lateral * leftNormal(unitVector(h)), h);
}

// ---------------------------------------------------------------------------------------------
// The vehicle

TEST(SkidSteerVehicle, DrivesStraightTwoMetresInTwoSecondsAtOneMetrePerSecond) {
  SkidSteerVehicle vehicle(Pose2(1, 2, degToRad(30)), VehicleLimits{}, 1.0);
  for (int i = 0; i < 40; ++i) vehicle.step({1.0, 0.0}, kDt);
  EXPECT_POSE_NEAR(vehicle.pose(), Pose2(1 + 2 * std::cos(degToRad(30)), 2 + 2 * std::sin(degToRad(30)), degToRad(30)),
                   1e-12);
  EXPECT_NEAR(vehicle.odometer(), 2.0, 1e-12);
}

TEST(SkidSteerVehicle, ConstantTurnRateTracesACircleOfRadiusSpeedOverTurnRate) {
  // v = 0.5 m/s, ω = 0.25 rad/s: radius 2 m about (0, 2); a quarter circle (π/2 / ω = 2π s) ends at
  // (2, 2) heading +90°, whatever the step.
  const double v = 0.5, omega = 0.25, quarter = (kPi / 2) / omega;
  for (int steps : {1, 7, 100}) {
    SkidSteerVehicle vehicle(Pose2(), VehicleLimits{}, v);
    for (int i = 0; i < steps; ++i) vehicle.step({v, omega}, quarter / steps);
    EXPECT_POSE_NEAR(vehicle.pose(), Pose2(2, 2, kPi / 2), 1e-12) << steps << " steps";
    EXPECT_NEAR(vehicle.odometer(), 2 * kPi / 2, 1e-12);
  }
  // Every intermediate pose stays on the circle |p − (0, 2)| = 2 (turning right: centre (0, −2)).
  SkidSteerVehicle right(Pose2(), VehicleLimits{}, v);
  for (int i = 0; i < 50; ++i) {
    right.step({v, -omega}, 0.1);
    EXPECT_NEAR((right.pose().translation() - Vec2(0, -2)).norm(), 2.0, 1e-12);
    EXPECT_NEAR(right.pose().heading(), normalizeAngle(-omega * 0.1 * (i + 1)), 1e-12);
  }
}

TEST(SkidSteerVehicle, ClampsSpeedTurnRateAndAcceleration) {
  VehicleLimits limits;  // 1 m/s, 0 min, 0.6 rad/s, 0.5 m/s²
  SkidSteerVehicle vehicle(Pose2(), limits, 0.0);
  // From rest, 2 m/s asked: +0.5 m/s² · 0.1 s = 0.05 m/s; 3 rad/s asked: 0.6 rad/s.
  VehicleCommand applied = vehicle.step({2.0, 3.0}, 0.1);
  EXPECT_DOUBLE_EQ(applied.speed_mps, 0.05);
  EXPECT_DOUBLE_EQ(applied.turn_rate_rad_s, 0.6);
  EXPECT_DOUBLE_EQ(vehicle.speed(), 0.05);
  EXPECT_NEAR(vehicle.pose().heading(), 0.06, 1e-12);
  applied = vehicle.step({0.0, -5.0}, 0.1);
  EXPECT_DOUBLE_EQ(applied.turn_rate_rad_s, -0.6);
  EXPECT_DOUBLE_EQ(applied.speed_mps, 0.0);  // 0.05 − 0.05
  // Full speed is capped at max_speed_mps once reached, 2 s after a standing start.
  for (int i = 0; i < 40; ++i) applied = vehicle.step({5.0, 0.0}, 0.1);
  EXPECT_DOUBLE_EQ(applied.speed_mps, 1.0);
  // Reverse asked, min speed 0: it slows by 0.05 m/s per 0.1 s, never below 0.
  applied = vehicle.step({-1.0, 0.0}, 0.1);
  EXPECT_DOUBLE_EQ(applied.speed_mps, 0.95);
  for (int i = 0; i < 40; ++i) applied = vehicle.step({-1.0, 0.0}, 0.1);
  EXPECT_DOUBLE_EQ(applied.speed_mps, 0.0);
  // Turning in place is allowed (skid steer).
  const Vec2 before = vehicle.pose().translation();
  vehicle.step({0.0, 0.5}, 1.0);
  EXPECT_VEC2_NEAR(vehicle.pose().translation(), before, 1e-15);
}

TEST(SkidSteerVehicle, RejectsBadStepsAndInitialSpeeds) {
  SkidSteerVehicle vehicle;
  EXPECT_THROW(vehicle.step({0.5, 0.0}, 0.0), InvalidInput);
  EXPECT_THROW(vehicle.step({std::nan(""), 0.0}, 0.1), InvalidInput);
  EXPECT_THROW(SkidSteerVehicle(Pose2(), VehicleLimits{}, 1.5), InvalidInput);
  VehicleLimits bad;
  bad.max_accel_mps2 = 0;
  EXPECT_THROW(SkidSteerVehicle(Pose2(), bad), InvalidInput);
}

// ---------------------------------------------------------------------------------------------
// Dense paths

TEST(DensePath, SpacesAnLShapedPolylineAndGivesItsHeadings) {
  // 3 m east then 2 m north, spacing 0.4: 8 pieces east (0.375 m), 5 pieces north (0.4 m).
  const Polyline2 line({Vec2(0, 0), Vec2(3, 0), Vec2(3, 2)});
  const std::vector<PathPoint> path = densePath(line, 0.4);
  ASSERT_EQ(path.size(), 14u);
  for (std::size_t i = 0; i < path.size(); ++i) {
    const double s = i <= 8 ? 0.375 * i : 3.0 + 0.4 * (i - 8);
    EXPECT_NEAR(path[i].s, s, 1e-12) << i;
    const Vec2 expected = i <= 8 ? Vec2(s, 0) : Vec2(3, s - 3);
    EXPECT_VEC2_NEAR(path[i].position, expected, 1e-12) << i;
    EXPECT_NEAR(path[i].heading, i < 8 ? 0.0 : kPi / 2, 1e-12) << i;  // the corner takes the leaving segment's
    if (i > 0) {
      EXPECT_LE((path[i].position - path[i - 1].position).norm(), 0.4 + 1e-12);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Progress tracking

TEST(PathTracker, ProgressIsMonotonicSoAPathComingBackNearItselfDoesNotMakeItJump) {
  // East 10 m along y = 0, a U-turn of radius 1, back west along y = 2.
  const Polyline2 hairpin = RouteBuilder(Vec2(0, 0), 0.0).straight(10).arc(1, 180).straight(10).build();
  PathTracker tracker(densePath(hairpin, 0.1));
  for (double x : {0.0, 1.0, 2.0, 3.0, 4.0}) EXPECT_NEAR(tracker.update(Vec2(x, 0.0)).s, x, 1e-9);
  // At (5, 1.2) the return leg (0.8 m away) is closer than the outbound leg (1.2 m): progress stays
  // on the outbound leg, at s = 5, 1.2 m to its left.
  const PathTracker::Closest c = tracker.update(Vec2(5.0, 1.2));
  EXPECT_NEAR(c.s, 5.0, 1e-9);
  EXPECT_NEAR(c.lateral, 1.2, 1e-9);
  // A position behind the progress maps to the progress, not back.
  EXPECT_NEAR(tracker.update(Vec2(2.0, 0.0)).s, 5.0, 1e-9);
  // Beyond the end, pointAt continues straight along the last heading (west).
  EXPECT_VEC2_NEAR(tracker.pointAt(tracker.endS() + 2.0), Vec2(-2.0, 2.0), 1e-9);
  EXPECT_NEAR(tracker.length(), hairpin.length(), 1e-9);
  EXPECT_THROW(PathTracker(densePath(Polyline2({Vec2(0, 0)}), 0.1)), InvalidInput);
}

// ---------------------------------------------------------------------------------------------
// Pure pursuit

TEST(PurePursuit, CommandsTheArcThroughTheGoalPoint) {
  // A straight path along y = −1; the vehicle at the origin heading east. Closest point (0, −1),
  // goal 1.5 m further (1.5, −1): κ = 2 · (−1) / (1.5² + 1²) = −8/13, turn rate 0.6 · κ.
  PurePursuit pursuit(densePath(Polyline2({Vec2(-5, -1), Vec2(50, -1)}), 0.25));
  const VehicleCommand cmd = pursuit.command(Pose2());
  EXPECT_VEC2_NEAR(pursuit.goal(), Vec2(1.5, -1), 1e-9);
  EXPECT_DOUBLE_EQ(cmd.speed_mps, 0.6);
  EXPECT_NEAR(cmd.turn_rate_rad_s, 0.6 * -8.0 / 13.0, 1e-9);
  EXPECT_NEAR(pursuit.crossTrackError(Pose2()), 1.0, 1e-9);  // left of the path
  EXPECT_FALSE(pursuit.finished(Pose2()));
  // Heading north, the goal is at (−1, −1.5) in the vehicle frame: κ = 2 · (−1.5) / 3.25, turn rate
  // 0.6 · κ = −0.554 rad/s, clamped to a 0.3 rad/s limit.
  VehicleLimits slow_turns;
  slow_turns.max_turn_rate_rad_s = 0.3;
  PurePursuit north(densePath(Polyline2({Vec2(-5, -1), Vec2(50, -1)}), 0.25), PurePursuitOptions{}, VehicleLimits{});
  EXPECT_NEAR(north.command(Pose2(0, 0, kPi / 2)).turn_rate_rad_s, 0.6 * -3.0 / 3.25, 1e-9);
  PurePursuit clamped(densePath(Polyline2({Vec2(-5, -1), Vec2(50, -1)}), 0.25), PurePursuitOptions{}, slow_turns);
  EXPECT_DOUBLE_EQ(clamped.command(Pose2(0, 0, kPi / 2)).turn_rate_rad_s, -0.3);
}

TEST(PurePursuit, SlowsDownNearTheEndAndFinishesWithinTenCentimetresOrPastIt) {
  const std::vector<PathPoint> path = densePath(Polyline2({Vec2(0, 0), Vec2(10, 0)}), 0.25);
  PurePursuit pursuit(path);
  // 0.25 m left: √(2 · 0.25 · 0.25) = 0.354 m/s.
  EXPECT_NEAR(pursuit.command(Pose2(9.75, 0, 0)).speed_mps, std::sqrt(2 * 0.25 * 0.25), 1e-9);
  EXPECT_FALSE(pursuit.finished(Pose2(9.85, 0, 0)));
  EXPECT_TRUE(pursuit.finished(Pose2(9.95, 0, 0)));
  EXPECT_TRUE(pursuit.finished(Pose2(10.5, 0.3, 0)));  // past it
  const VehicleCommand stop = pursuit.command(Pose2(9.95, 0, 0));
  EXPECT_EQ(stop.speed_mps, 0.0);
  EXPECT_EQ(stop.turn_rate_rad_s, 0.0);
}

TEST(PurePursuit, FollowsACurvyRouteWithinTenCentimetresAndFinishesAtItsEnd) {
  const Polyline2 route = curvyRoute();
  ASSERT_GT(route.length(), 80.0);
  ASSERT_LT(route.length(), 120.0);
  PurePursuit pursuit(densePath(route, 0.2));
  const RunResult r = drive(pursuit, route, Pose2(route.front(), route.headingAt(0)));
  report("pure pursuit, on path", r);
  EXPECT_TRUE(r.finished);
  EXPECT_LE(r.max_error, 0.1);
  EXPECT_LE(r.end_distance, 0.1);
  EXPECT_NEAR(r.driven, route.length(), 0.2);
}

TEST(PurePursuit, ConvergesFromAHalfMetreOffsetWithinTenMetres) {
  const Polyline2 route = curvyRoute();
  for (double lateral : {0.5, -0.5}) {
    PurePursuit pursuit(densePath(route, 0.2));
    const RunResult r = drive(pursuit, route, offsetStart(route, lateral));
    report("pure pursuit, offset " + std::to_string(lateral), r);
    EXPECT_TRUE(r.finished);
    EXPECT_NEAR(r.max_error, 0.5, 1e-9);  // the start
    EXPECT_LE(r.max_error_after_10m, 0.1);
    EXPECT_LE(r.end_distance, 0.1);
  }
}

// ---------------------------------------------------------------------------------------------
// The paper's servo, dτ/dt = γ · x

// A path that starts behind the vehicle (the way back from an out-and-back via point): it turns
// in place at the limits' turn rate, 0.6 rad/s, from 180 deg off to within 10 deg (170 deg: 4.95 s,
// 99 steps of 0.05 s), without moving, then follows the path.
TEST(PurePursuit, FacingAwayFromThePathItTurnsInPlaceFirst) {
  PurePursuit pursuit(densePath(Polyline2({Vec2(10, 0), Vec2(0, 0)}), 0.25));  // westward
  SkidSteerVehicle vehicle(Pose2(10, 0, 0));                                    // facing east
  const VehicleCommand first = pursuit.command(vehicle.pose());
  EXPECT_EQ(first.speed_mps, 0.0);
  EXPECT_DOUBLE_EQ(first.turn_rate_rad_s, 0.6);  // at exactly 180 deg: to the left
  EXPECT_TRUE(pursuit.turningInPlace());
  std::size_t steps = 0;
  while (pursuit.turningInPlace()) {
    vehicle.step(pursuit.command(vehicle.pose()), 0.05);
    ++steps;
    ASSERT_LT(steps, 200u);
  }
  // The 100th command finds it within 10 deg and pursues: its step drives off at 0.025 m/s (the
  // 0.5 m/s^2 acceleration limit), 1.25 mm; before it, the vehicle had not moved.
  EXPECT_EQ(steps, 100u);
  EXPECT_NEAR((vehicle.pose().translation() - Vec2(10, 0)).norm(), 0.00125, 1e-6);
  for (int i = 0; i < 400 && !pursuit.finished(vehicle.pose()); ++i) vehicle.step(pursuit.command(vehicle.pose()), 0.05);
  EXPECT_TRUE(pursuit.finished(vehicle.pose()));
  // Below turn_in_place_deg (90) it does not: 80 deg off, pure pursuit turns while driving.
  PurePursuit gentle(densePath(Polyline2({Vec2(0, 0), Vec2(10, 0)}), 0.25));
  EXPECT_GT(gentle.command(Pose2(0, 0, degToRad(80))).speed_mps, 0.0);
  EXPECT_FALSE(gentle.turningInPlace());
}

TEST(CenterServo, TurnsByGammaTimesTheImageAbscissaOfTheRoadCentre) {
  const auto camera = testing::terregatorPinhole();
  const double beta = degToRad(22.0);
  // The road centre along y = −0.5; from the origin the point 2.5 m ahead is (2.5, −0.5) in the
  // vehicle frame, 0.5 m right: depth 2.5 cos β + 1.5 sin β along the optical axis,
  // x = 904 · 0.5 / depth > 0.
  CenterServo servo(densePath(Polyline2({Vec2(-5, -0.5), Vec2(50, -0.5)}), 0.25), *camera);
  const VehicleCommand cmd = servo.command(Pose2());
  const double x = 904.0 * 0.5 / (2.5 * std::cos(beta) + 1.5 * std::sin(beta));  // 156.95 px
  EXPECT_TRUE(servo.lastObservation().in_image);
  EXPECT_VEC2_NEAR(servo.lastObservation().target_vehicle, Vec2(2.5, -0.5), 1e-9);
  EXPECT_NEAR(servo.lastObservation().x_px, x, 1e-6);
  EXPECT_NEAR(cmd.turn_rate_rad_s, -CenterServoOptions{}.gain * x, 1e-9);  // right: negative
  // The matched gain turns as linearised pure pursuit, 2 v y / L² = 2 · 0.6 · (−0.5) / 2.5² = −0.096
  // (to γ's 4 digits; pure pursuit proper, 2 v y / (x² + y²), gives −0.092).
  EXPECT_NEAR(cmd.turn_rate_rad_s, -0.096, 1e-4);
  EXPECT_DOUBLE_EQ(cmd.speed_mps, 0.6);

  // The centre straight ahead: x = 0, no turn.
  CenterServo ahead(densePath(Polyline2({Vec2(-5, 0), Vec2(50, 0)}), 0.25), *camera);
  EXPECT_NEAR(ahead.command(Pose2()).turn_rate_rad_s, 0.0, 1e-12);
  EXPECT_NEAR(ahead.lastObservation().pixel.x(), 255.5, 1e-9);
}

TEST(CenterServo, FallsBackToTheBearingOutsideTheImage) {
  // The centre 3 m right at 2.5 m ahead: beyond the image's ±0.82 m there. Turn rate γ · fx · bearing.
  const auto camera = testing::terregatorPinhole();
  CenterServo servo(densePath(Polyline2({Vec2(-5, -3), Vec2(50, -3)}), 0.25), *camera);
  const VehicleCommand cmd = servo.command(Pose2());
  EXPECT_FALSE(servo.lastObservation().in_image);
  EXPECT_NEAR(cmd.turn_rate_rad_s, CenterServoOptions{}.gain * 904.0 * std::atan2(-3.0, 2.5), 1e-9);
  // A centre behind the vehicle: turn towards it, clamped to the limit.
  EXPECT_DOUBLE_EQ(servo.command(Pose2(0, 0, kPi - 0.3)).turn_rate_rad_s, 0.6);
}

TEST(CenterServo, DefaultGainMatchesPurePursuitForTheTerregatorCamera) {
  const auto camera = testing::terregatorPinhole();
  const double beta = degToRad(22.0);
  const double expected = 2 * 0.6 * (2.5 * std::cos(beta) + 1.5 * std::sin(beta)) / (904.0 * 2.5 * 2.5);
  EXPECT_NEAR(CenterServo::matchedGain(*camera, 2.5, 0.6), expected, 1e-9);
  EXPECT_DOUBLE_EQ(CenterServoOptions{}.lookahead_m, 2.5);
  EXPECT_NEAR(CenterServoOptions{}.gain, expected, 1e-7);
  // Twice the speed, twice the gain; and for a point 4 m ahead: 2 · 0.6 · 4.271 / (904 · 4²).
  EXPECT_NEAR(CenterServo::matchedGain(*camera, 2.5, 1.2), 2 * expected, 1e-9);
  EXPECT_NEAR(CenterServo::matchedGain(*camera, 4.0, 0.6),
              2 * 0.6 * (4 * std::cos(beta) + 1.5 * std::sin(beta)) / (904.0 * 16.0), 1e-9);
  EXPECT_THROW(CenterServo::matchedGain(*camera, 0.0, 0.6), InvalidInput);
}

TEST(CenterServo, FollowsACurvyRouteWithinTenCentimetresAndFinishesAtItsEnd) {
  const auto camera = testing::terregatorPinhole();
  const Polyline2 route = curvyRoute();
  CenterServo servo(densePath(route, 0.2), *camera);
  const RunResult r = drive(servo, route, Pose2(route.front(), route.headingAt(0)));
  report("center servo, on path", r);
  EXPECT_EQ(r.fallbacks, 0);  // the image law alone: the road centre never leaves the image
  EXPECT_TRUE(r.finished);
  EXPECT_LE(r.max_error, 0.1);
  EXPECT_LE(r.end_distance, 0.1);
  EXPECT_NEAR(r.driven, route.length(), 0.2);
}

TEST(CenterServo, ConvergesFromAHalfMetreOffsetWithinTenMetres) {
  const auto camera = testing::terregatorPinhole();
  const Polyline2 route = curvyRoute();
  for (double lateral : {0.5, -0.5}) {
    CenterServo servo(densePath(route, 0.2), *camera);
    const RunResult r = drive(servo, route, offsetStart(route, lateral));
    report("center servo, offset " + std::to_string(lateral), r);
    EXPECT_EQ(r.fallbacks, 0);
    EXPECT_TRUE(r.finished);
    EXPECT_NEAR(r.max_error, 0.5, 1e-9);
    EXPECT_LE(r.max_error_after_10m, 0.1);
    EXPECT_LE(r.end_distance, 0.1);
  }
}

// ---------------------------------------------------------------------------------------------
// Options

template <typename Options>
void expectFieldNamed(const Options& options, const std::string& text) {
  try {
    options.validate();
    ADD_FAILURE() << "no exception for " << text;
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
  }
}

TEST(SteeringOptions, DefaultsAreValidAndBadFieldsAreNamed) {
  EXPECT_NO_THROW(VehicleLimits{}.validate());
  EXPECT_NO_THROW(PurePursuitOptions{}.validate());
  EXPECT_NO_THROW(CenterServoOptions{}.validate());

  VehicleLimits limits;
  limits.max_speed_mps = 0;
  expectFieldNamed(limits, "VehicleLimits::max_speed_mps = 0");
  limits = {};
  limits.min_speed_mps = 2;
  expectFieldNamed(limits, "VehicleLimits::min_speed_mps = 2");
  limits = {};
  limits.max_turn_rate_rad_s = -1;
  expectFieldNamed(limits, "VehicleLimits::max_turn_rate_rad_s = -1");
  limits = {};
  limits.max_accel_mps2 = std::nan("");
  expectFieldNamed(limits, "VehicleLimits::max_accel_mps2");

  PurePursuitOptions pursuit;
  pursuit.lookahead_m = 0;
  expectFieldNamed(pursuit, "PurePursuitOptions::lookahead_m = 0");
  pursuit = {};
  pursuit.speed_mps = -0.5;
  expectFieldNamed(pursuit, "PurePursuitOptions::speed_mps = -0.5");

  CenterServoOptions servo;
  servo.lookahead_m = -1;
  expectFieldNamed(servo, "CenterServoOptions::lookahead_m = -1");
  servo = {};
  servo.gain = 0;
  expectFieldNamed(servo, "CenterServoOptions::gain = 0");
  servo = {};
  servo.speed_mps = 0;
  expectFieldNamed(servo, "CenterServoOptions::speed_mps = 0");

  // The followers validate what they are given.
  const auto camera = testing::terregatorPinhole();
  const std::vector<PathPoint> path = densePath(Polyline2({Vec2(0, 0), Vec2(10, 0)}), 0.5);
  pursuit = {};
  pursuit.lookahead_m = 0;
  EXPECT_THROW(PurePursuit(path, pursuit), InvalidInput);
  servo = {};
  servo.gain = -1;
  EXPECT_THROW(CenterServo(path, *camera, servo), InvalidInput);
}

/// The InvalidInput message of `f()`, or "" when it does not throw.
template <typename F>
std::string rejection(F f) {
  try {
    f();
  } catch (const InvalidInput& e) {
    return e.what();
  }
  return "";
}

TEST(SteeringOptions, TheRulesBetweenFieldsAndTheArgumentsAreWordedExactly) {
  PurePursuitOptions pursuit;
  pursuit.turn_in_place_until_deg = 95;  // beyond turn_in_place_deg
  EXPECT_EQ(rejection([&] { pursuit.validate(); }),
            "PurePursuitOptions::turn_in_place_until_deg = 95: must be in (0, turn_in_place_deg)");
  pursuit.turn_in_place_until_deg = 0;
  EXPECT_EQ(rejection([&] { pursuit.validate(); }),
            "PurePursuitOptions::turn_in_place_until_deg = 0: must be in (0, turn_in_place_deg)");
  pursuit = {};
  pursuit.turn_in_place_deg = 181;
  EXPECT_EQ(rejection([&] { pursuit.validate(); }), "PurePursuitOptions::turn_in_place_deg = 181: must be in (0, 180]");
  pursuit = {};
  pursuit.speed_mps = std::numeric_limits<double>::infinity();
  EXPECT_EQ(rejection([&] { pursuit.validate(); }), "PurePursuitOptions::speed_mps = inf: must be finite and > 0");

  VehicleLimits limits;
  limits.min_speed_mps = 2;
  EXPECT_EQ(rejection([&] { limits.validate(); }), "VehicleLimits::min_speed_mps = 2: must be <= max_speed_mps");
  limits.min_speed_mps = std::nan("");
  EXPECT_EQ(rejection([&] { limits.validate(); }), "VehicleLimits::min_speed_mps = nan: must be finite");

  const std::vector<PathPoint> path = densePath(Polyline2({Vec2(0, 0), Vec2(10, 0)}), 0.5);
  EXPECT_EQ(rejection([&] { PathTracker(path, 0.0); }), "PathTracker: window_m = 0: must be finite and > 0");
  const auto camera = testing::terregatorPinhole();
  EXPECT_EQ(rejection([&] { CenterServo::matchedGain(*camera, 0.0, 0.6); }),
            "CenterServo::matchedGain: lookahead_m = 0: must be finite and > 0");
  EXPECT_EQ(rejection([&] { CenterServo::matchedGain(*camera, 2.5, -1.0); }),
            "CenterServo::matchedGain: speed_mps = -1: must be finite and > 0");
  SkidSteerVehicle vehicle;
  EXPECT_EQ(rejection([&] { vehicle.step({0.5, 0.0}, 0.0); }),
            "SkidSteerVehicle::step: dt = 0: must be finite and > 0");
  EXPECT_EQ(rejection([&] { vehicle.step({std::nan(""), 0.0}, 0.1); }),
            "SkidSteerVehicle::step: command.speed_mps = nan: must be finite");
  EXPECT_EQ(rejection([&] { vehicle.step({0.0, INFINITY}, 0.1); }),
            "SkidSteerVehicle::step: command.turn_rate_rad_s = inf: must be finite");
  EXPECT_EQ(rejection([&] { SkidSteerVehicle(Pose2(), VehicleLimits{}, 1.5); }),
            "SkidSteerVehicle: speed_mps = 1.5: must be in [min_speed_mps, max_speed_mps]");
}

}  // namespace
}  // namespace mapnav
