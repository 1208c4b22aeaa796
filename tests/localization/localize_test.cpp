// localize(), the Map module's step: the correspondences it builds (labelled, piecewise on curves,
// park mode's centre line), the pixel noise across a line, and the filter it drives.
#include "mapnav/localization/localize.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include "line_scene.h"
#include "map_fixtures.h"
#include "mapnav/core/error.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/localization/correspondences.h"
#include "mapnav/localization/line_fit.h"
#include "mapnav/map/map.h"
#include "mapnav/map/predict.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"
#include "mapnav/tokens/detected_object.h"

namespace mapnav {
namespace {

using namespace line_scene;

// The Terregator camera (1.5 m up, 22 deg down, f = 904 px). A line across the road 10 m ahead
// on the optical axis's plane lies on one image row v0 = cy + f tan(theta - tilt), theta =
// atan(h / 10): a pixel across it is the next row, whose ground distance is h / tan(tilt +
// atan((v0 -+ 1 - cy) / f)) (about (d^2 + h^2) cos^2(theta - tilt) / (h f) = 7.1 cm from the
// 10 m). A line along the road there is a column: a pixel across it is Z / f to the side, Z the
// point's depth on the optical axis, sqrt(d^2 + h^2) cos(theta - tilt) (1.1 cm).
TEST(MatchingNoise, GroundMetresPerPixelIsTheCameraResolutionAcrossTheLine) {
  CameraIntrinsics in;
  in.fx = in.fy = 904;
  CameraMount mount;
  mount.height_m = 1.5;
  mount.tilt_rad = degToRad(22.0);
  const auto camera = createCamera(LensModel::Pinhole, in, mount);
  const double h = 1.5, d = 10.0, tilt = mount.tilt_rad, theta = std::atan(h / d);
  const double v0 = in.cy + in.fx * std::tan(theta - tilt);
  auto rowDistance = [&](double v) { return h / std::tan(tilt + std::atan((v - in.cy) / in.fy)); };
  const double up = rowDistance(v0 - 1) - d, down = d - rowDistance(v0 + 1);

  const auto across = groundMetresPerPixel(*camera, Segment2{{d, -0.5}, {d, 0.5}});
  ASSERT_TRUE(across);
  EXPECT_GE(*across, std::min(up, down) - 1e-9);
  EXPECT_LE(*across, std::max(up, down) + 1e-9);
  EXPECT_NEAR(*across, 0.071, 0.001);

  const auto along = groundMetresPerPixel(*camera, Segment2{{d - 0.5, 0.0}, {d + 0.5, 0.0}});
  ASSERT_TRUE(along);
  EXPECT_NEAR(*along, std::hypot(d, h) * std::cos(theta - tilt) / in.fx, 1e-9);

  // Behind the camera: not seen.
  EXPECT_FALSE(groundMetresPerPixel(*camera, Segment2{{-3.0, -0.5}, {-3.0, 0.5}}));
}

// ---------------------------------------------------------------------------------------------
// localize: the Map module's step

// A Prediction holding the scene's interest segments (what predictView would give near the
// crossing), and the DetectedObject a detector at `truth` would report of `lines`.
Prediction scenePrediction() {
  Prediction p;
  const std::pair<const char*, Segment2> segments[] = {{"R1.left.0", kLeft},      {"R1.right.0", kRight},
                                                       {"R2.near.0", kCrossNear}, {"R2.far.0", kCrossFar},
                                                       {"R3.near.0", kCrossNear}};
  for (const auto& [id, world] : segments) {
    InterestSegment s;
    s.id = id;
    p.view.segments.push_back(s);
    p.segments_world.push_back(world);
  }
  return p;
}

DetectedObject detectedFrom(const std::vector<LineCorrespondence>& lines, double timestamp) {
  DetectedObject d;
  d.timestamp = timestamp;
  d.confidence = 1;
  for (const LineCorrespondence& c : lines) {
    DetectedLine l;
    l.label = c.id;
    l.score = 1;
    l.vehicle = c.detected_vehicle;
    d.lines.push_back(l);
  }
  return d;
}

TEST(MatchingLocalize, EdgesCorrectLateralAndHeadingAndTheCrossingCorrectsAlong) {
  // Driving along the road at y = 0.3 from x = 0, 0.5 m a frame, odometry 2 % long (a bias the noise model
  // covers only as random error). The road edges
  // are seen every frame (2 cm noise); the crossing at x = 19..21 once within 9 m of it.
  const Prediction prediction = scenePrediction();
  const Pose2 start(0, 0.3, 0);
  PoseFilter filter(Pose2(0, 0.2, degToRad(1.0)), diagonalCovariance(0.1, 2.0), twoPercentOdometry());
  std::mt19937_64 rng(5);
  double worst_lateral = 0, along_before = 0, along_after = 0, sigma_along_before = 0, sigma_along_after = 0;
  for (int k = 1; k <= 24; ++k) {
    const Pose2 truth(start.x() + 0.5 * k, start.y(), 0);
    std::vector<LineCorrespondence> seen = roadEdges(truth, 0.02, &rng);
    const bool crossing_in_view = 19 - truth.x() < 9;
    if (crossing_in_view) {
      for (const LineCorrespondence& c : crossingEdges(truth, 0.02, &rng)) seen.push_back(c);
    }
    const CurrentPosition out = localize(filter, {0.5 * 1.02, 0.0}, prediction, detectedFrom(seen, 0.1 * k));
    ASSERT_EQ(out.status, PositionStatus::Corrected) << "frame " << k << ": " << out.reason;
    const Vec3 e = poseError(out.pose, truth);
    EXPECT_TRUE(out.observed_lateral && out.observed_heading);
    EXPECT_EQ(out.observed_along, crossing_in_view) << "frame " << k;
    // Every frame's lateral and heading errors within 4 reported sigmas.
    EXPECT_LT(std::abs(e.y()), 4 * std::sqrt(out.covariance(1, 1))) << "frame " << k;
    EXPECT_LT(std::abs(e.z()), 4 * std::sqrt(out.covariance(2, 2))) << "frame " << k;
    if (!crossing_in_view) {
      if (k >= 10) worst_lateral = std::max(worst_lateral, std::abs(e.y()));  // once settled
      along_before = e.x();
      sigma_along_before = std::sqrt(out.covariance(0, 0));
      EXPECT_NE(out.reason.find("along-road position from odometry"), std::string::npos) << out.reason;
    } else {
      along_after = e.x();
      sigma_along_after = std::sqrt(out.covariance(0, 0));
    }
  }
  std::printf("edges only: lateral error <= %.4f m (from frame 10), along error grew to %.3f m (sigma %.3f m); "
              "after the crossing came into view: %.4f m (sigma %.4f m)\n",
              worst_lateral, along_before, sigma_along_before, along_after, sigma_along_after);
  EXPECT_LT(worst_lateral, 0.03);  // 1 cm sigma by then
  EXPECT_GT(along_before, 0.15);  // 2 % of 10 m, carried by odometry
  EXPECT_LT(std::abs(along_before), 3 * sigma_along_before);  // and covered by the covariance
  EXPECT_LT(std::abs(along_after), 0.05);
  EXPECT_LT(std::abs(along_after), 4 * sigma_along_after);
}

TEST(MatchingLocalize, NoUsableLinesLeaveThePoseToOdometry) {
  const Prediction prediction = scenePrediction();
  PoseFilter filter(kTruth, diagonalCovariance(0.05, 1.0));
  const CurrentPosition failed =
      localize(filter, {1.0, 0.0}, prediction, DetectedObject::failed("frame over-exposed"));
  EXPECT_EQ(failed.status, PositionStatus::OdometryOnly);
  EXPECT_NE(failed.reason.find("vision failed (frame over-exposed)"), std::string::npos) << failed.reason;
  const double h = kTruth.heading();
  EXPECT_POSE_NEAR(failed.pose, Pose2(kTruth.x() + std::cos(h), kTruth.y() + std::sin(h), h), 1e-12);

  DetectedObject unknown = detectedFrom(roadEdges(filter.pose(), 0.05), 2.0);
  for (DetectedLine& l : unknown.lines) l.label = "R9.left.0";  // not in the prediction
  const CurrentPosition none = localize(filter, {0.0, 0.0}, prediction, unknown);
  EXPECT_EQ(none.status, PositionStatus::OdometryOnly);
  EXPECT_NE(none.reason.find("no usable lines"), std::string::npos) << none.reason;
  EXPECT_EQ(none.lines_used, 0);
  EXPECT_DOUBLE_EQ(none.timestamp, 2.0);
}

TEST(MatchingLocalize, ParkModeCentreLineCorrectsLateralAndHeadingNotAlong) {
  // The cross of four roads: R1 runs from (0, 0) east. The vehicle is at (8, 0.3) heading 3 degrees
  // left; the filter thinks (8.5, 0), heading 0, with 0.5 m / 5 degree sigmas. Vision finds the
  // centre line 2 to 8 m ahead and no labelled edge.
  const Map map(testing::crossOfFourRoads());
  const Pose2 truth(8.0, 0.3, degToRad(3.0));
  const Pose2 prior(8.5, 0.0, 0.0);
  PoseFilter filter(prior, diagonalCovariance(0.5, 5.0));
  DetectedObject d;
  d.timestamp = 1.0;
  d.centerline_vehicle = truth.inverse().transform(Segment2{{10, 0}, {16, 0}});
  const CurrentPosition out = localize(filter, {0.0, 0.0}, Prediction{}, d, {}, &map);
  ASSERT_EQ(out.status, PositionStatus::Corrected) << out.reason;
  const Vec3 e = poseError(out.pose, truth);
  std::printf("park mode: %s; errors along %+.4f m, lateral %+.4f m, heading %+.4f deg\n", out.reason.c_str(), e.x(),
              e.y(), radToDeg(e.z()));
  EXPECT_NE(out.reason.find("park mode"), std::string::npos);
  EXPECT_NEAR(out.pose.x(), prior.x(), 1e-9);  // along: untouched
  EXPECT_LT(std::abs(e.y()), 0.01);            // lateral: from 0.3 m to under 1 cm
  EXPECT_LT(std::abs(radToDeg(e.z())), 0.1);   // heading: from 3 degrees to under 0.1
  EXPECT_TRUE(out.observed_lateral);
  EXPECT_TRUE(out.observed_heading);
  EXPECT_FALSE(out.observed_along);
  EXPECT_EQ(out.lines_used, 1);

  // Without the map (or far from every road) there is nothing to match.
  PoseFilter lost(Pose2(8.5, 9.0, 0.0), diagonalCovariance(0.5, 5.0));
  EXPECT_EQ(localize(lost, {0.0, 0.0}, Prediction{}, d, {}, &map).status, PositionStatus::OdometryOnly);
  EXPECT_EQ(localize(filter, {0.0, 0.0}, Prediction{}, d).status, PositionStatus::OdometryOnly);
}

TEST(MatchingOnCurve, PiecewiseEdgesFollowTheCurveWhereThePredictedChordsDoNot) {
  // On the campus' R5, a 35 m radius curve, the vehicle 20 m from I4 facing along the road. Vision's
  // lines are short chords of the edges (2.4 m: 2 cm from the curve, as the image polygon's 3 px
  // tolerance gives), breaking at other places than the prediction's 5 m chords (0.1 m tolerance).
  const Map& campus = testing::campusMap();
  const Road& r5 = campus.road("R5");
  const Pose2 truth(r5.centerline.pointAt(20.0), r5.centerline.headingAt(20.0));
  const auto camera = testing::terregatorPinhole();
  const Prediction prediction = predictView(campus, truth, *camera);
  DetectedObject detected;
  for (std::size_t i = 0; i < prediction.view.segments.size(); ++i) {
    const InterestSegment& s = prediction.view.segments[i];
    if (s.owner != "R5" || s.side == "corner") continue;
    const Polyline2& edge = s.side == "left" ? campus.leftEdge(r5) : campus.rightEdge(r5);
    const double sa = edge.project(prediction.segments_world[i].a).arc_length;
    const double sb = edge.project(prediction.segments_world[i].b).arc_length;
    for (double s0 = std::min(sa, sb) + 0.7; s0 + 2.4 <= std::max(sa, sb); s0 += 2.4) {
      DetectedLine line;
      line.label = s.id;
      line.vehicle = truth.inverse().transform(Segment2{edge.pointAt(s0), edge.pointAt(s0 + 2.4)});
      detected.lines.push_back(line);
    }
  }
  ASSERT_GE(detected.lines.size(), 4u);
  const auto chords = labelledCorrespondences(prediction, detected, 0.05, 0.3);
  const auto pieces = edgeCorrespondences(campus, prediction, detected, truth, 0.05, 0.3, 1.0);
  EXPECT_GT(pieces.size(), chords.size());
  auto worst = [&](const std::vector<LineCorrespondence>& lines) {  // largest end-point distance at the truth
    double d = 0;
    for (const LineCorrespondence& c : lines) {
      const Segment2 w = truth.transform(c.detected_vehicle);
      const Vec2 n = leftNormal((c.map_world.b - c.map_world.a).normalized());
      d = std::max({d, std::abs(n.dot(w.a - c.map_world.a)), std::abs(n.dot(w.b - c.map_world.a))});
    }
    return d;
  };
  std::printf("on the curve: end points up to %.3f m off the predicted chords, %.3f m off the edge pieces\n",
              worst(chords), worst(pieces));
  EXPECT_LT(worst(pieces), 0.025);
  EXPECT_GT(worst(chords), 2 * worst(pieces));
  // Fitted from the truth, the pieces stay on it; the chords pull it away.
  const auto fit_pieces = fitPoseToLines(truth, pieces);
  const auto fit_chords = fitPoseToLines(truth, chords);
  ASSERT_TRUE(fit_pieces && fit_chords);
  const Vec3 e_pieces = poseError(fit_pieces->pose, truth), e_chords = poseError(fit_chords->pose, truth);
  std::printf("fit from the truth: pieces off by %.4f m, %.3f deg; chords by %.4f m, %.3f deg\n",
              e_pieces.head<2>().norm(), radToDeg(std::abs(e_pieces.z())), e_chords.head<2>().norm(),
              radToDeg(std::abs(e_chords.z())));
  EXPECT_LT(e_pieces.head<2>().norm(), 0.02);
  EXPECT_LT(std::abs(radToDeg(e_pieces.z())), 0.1);
  EXPECT_GT(e_chords.head<2>().norm() + std::abs(e_chords.z()), e_pieces.head<2>().norm() + std::abs(e_pieces.z()));

  LocalizeOptions options;
  EXPECT_EQ(options.curve_piece_m, 1.0);  // the missions' default: pieces of at most 1 m
  options.curve_piece_m = -1;
  EXPECT_THROW(options.validate(), InvalidInput);
}

}  // namespace
}  // namespace mapnav
