#pragma once
// The scene the localization tests share: a straight road with a crossing road, detections of its
// edges from a true pose (with seeded noise), the prior of most tests, a notched edge for
// re-association, and the statistics the consistency checks compare against.
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <boost/math/distributions/chi_squared.hpp>

#include "mapnav/geometry/polyline2.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/localization/correspondences.h"
#include "mapnav/localization/localize.h"
#include "mapnav/localization/pose_filter.h"

namespace mapnav::line_scene {

// The scene of most tests: a road along +x, edges y = +1 (left) and y = -1 (right), and a crossing
// road whose edges x = 19 and x = 21 run along y. The vehicle drives along the first road.
inline const Segment2 kLeft{{-5, 1}, {40, 1}}, kRight{{-5, -1}, {40, -1}};
inline const Segment2 kCrossNear{{19, -10}, {19, 10}}, kCrossFar{{21, -10}, {21, 10}};

// The error of `estimate` against `truth` as (x, y, heading), the heading wrapped.
inline Vec3 poseError(const Pose2& estimate, const Pose2& truth) {
  return {estimate.x() - truth.x(), estimate.y() - truth.y(), normalizeAngle(estimate.heading() - truth.heading())};
}

// What a detector at `truth` reports of the world piece `seen` of map line `line`: its end points in
// the vehicle frame, each coordinate with Gaussian noise of `sigma` (none when rng is null).
inline LineCorrespondence detect(const std::string& id, const Pose2& truth, const Segment2& seen, const Segment2& line,
                          double sigma, std::mt19937_64* rng = nullptr) {
  Segment2 v = truth.inverse().transform(seen);
  if (rng != nullptr) {
    std::normal_distribution<double> noise(0.0, sigma);
    v.a += Vec2(noise(*rng), noise(*rng));
    v.b += Vec2(noise(*rng), noise(*rng));
  }
  return {id, v, line, sigma, {}};
}

// Both road edges seen from 2 to 8 m ahead of the vehicle (x along the road).
inline std::vector<LineCorrespondence> roadEdges(const Pose2& truth, double sigma, std::mt19937_64* rng = nullptr) {
  const double x = truth.x();
  return {detect("R1.left.0", truth, {{x + 2, 1}, {x + 8, 1}}, kLeft, sigma, rng),
          detect("R1.right.0", truth, {{x + 2, -1}, {x + 8, -1}}, kRight, sigma, rng)};
}

// The crossing road's edges beside the first road, left and right of it.
inline std::vector<LineCorrespondence> crossingEdges(const Pose2& truth, double sigma, std::mt19937_64* rng = nullptr) {
  return {detect("R2.near.0", truth, {{19, 1.5}, {19, 5}}, kCrossNear, sigma, rng),
          detect("R2.far.0", truth, {{21, 1.5}, {21, 5}}, kCrossFar, sigma, rng),
          detect("R3.near.0", truth, {{19, -5}, {19, -1.5}}, kCrossNear, sigma, rng)};
}

inline std::vector<LineCorrespondence> allEdges(const Pose2& truth, double sigma, std::mt19937_64* rng = nullptr) {
  std::vector<LineCorrespondence> out = roadEdges(truth, sigma, rng);
  for (const LineCorrespondence& c : crossingEdges(truth, sigma, rng)) out.push_back(c);
  return out;
}

inline const Pose2 kTruth(14.0, 0.2, degToRad(3.0));
// The prior: 0.3 m, -0.2 m, 2 degrees off.
inline const Pose2 kPrior(kTruth.x() + 0.3, kTruth.y() - 0.2, kTruth.heading() + degToRad(2.0));

// The two-sided interval holding the mean of `trials` chi-square(dof) draws with probability p.
inline std::pair<double, double> meanChiSquareInterval(int dof, int trials, double p) {
  boost::math::chi_squared_distribution<double> sum(dof * trials);
  return {boost::math::quantile(sum, (1 - p) / 2) / trials, boost::math::quantile(sum, (1 + p) / 2) / trials};
}

// The filter's options as its defaults were before they became the missions' (2 % odometry distance
// noise instead of 5 %): the figures of the filter and localize tests that predict with odometry
// were measured with them.
inline FilterOptions twoPercentOdometry() {
  FilterOptions f;
  f.motion.distance_sigma_per_m = 0.02;
  return f;
}

// A diagonal covariance over (x, y, heading): sigma_m in x and y, sigma_deg in the heading.
inline Mat3 diagonalCovariance(double sigma_m, double sigma_deg) {
  return Vec3(sigma_m * sigma_m, sigma_m * sigma_m, std::pow(degToRad(sigma_deg), 2)).asDiagonal();
}

// ---------------------------------------------------------------------------------------------
// Re-association

// A left road edge with a notch (as where a road meets a narrower one): y = 1, a recess to
// y = 1.3 for 10 <= x <= 12, y = 1 again up to the crossing at x = 19.
inline const Polyline2 kNotchedLeft({{-5, 1}, {10, 1}, {10, 1.3}, {12, 1.3}, {12, 1}, {19, 1}});

inline std::vector<Segment2> segmentsOf(const Polyline2& line) {
  std::vector<Segment2> out;
  for (std::size_t i = 0; i < line.segmentCount(); ++i) out.push_back(line.segment(i));
  return out;
}

// The notched edge seen before, in and after the notch, the right edge and the crossing; the
// left pieces carry the notched edge's segments as candidates and, as their first map line, the
// segment nearest to their midpoint placed by `prior` (as edgeCorrespondences picks it).
inline std::vector<LineCorrespondence> notchScene(const Pose2& truth, const Pose2& prior) {
  std::vector<LineCorrespondence> lines;
  const std::vector<Segment2> candidates = segmentsOf(kNotchedLeft);
  for (const auto& [id, seen] : {std::pair<const char*, Segment2>{"R1.left.0", {{4, 1}, {9.6, 1}}},
                                 std::pair<const char*, Segment2>{"R1.left.1", {{10.3, 1.3}, {11.7, 1.3}}},
                                 std::pair<const char*, Segment2>{"R1.left.2", {{12.3, 1}, {16, 1}}}}) {
    LineCorrespondence c = detect(id, truth, seen, Segment2{}, 0.05);
    const Vec2 mid = prior.transform(c.detected_vehicle.pointAt(0.5));
    c.map_world = kNotchedLeft.segment(kNotchedLeft.project(mid).segment);
    c.candidates = candidates;
    lines.push_back(c);
  }
  lines.push_back(detect("R1.right.0", truth, {{4, -1}, {16, -1}}, kRight, 0.05));
  for (const LineCorrespondence& c : crossingEdges(truth, 0.05)) lines.push_back(c);
  return lines;
}

inline const Pose2 kNotchTruth(3.0, 0.1, degToRad(2.0));
// 2 m along, 0.1 m across and 1 degree off: the notch piece (midpoint at x = 11 in truth) lands at
// x = 13, 0.34 m from the edge after the notch and 1 m from the notch.
inline const Pose2 kNotchPrior(5.0, 0.0, degToRad(3.0));

}  // namespace mapnav::line_scene
