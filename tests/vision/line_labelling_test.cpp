#include <gtest/gtest.h>

#include <optional>
#include <string>
#include <vector>

#include "mapnav/core/error.h"
#include "mapnav/vision/line_labelling.h"

namespace mapnav {
namespace {

// A crossing line 8 m ahead (the far side of an intersection) and a road edge 1 m to the left, and
// two detected lines: one 0.8 m beyond the crossing line (an estimate 0.8 m behind along the road),
// one 0.6 m left of the road edge. The gate at an end point p is max(max_distance_m 0.4,
// gate_sigma 3 x the predicted line's sigma across itself at p, no further than halfway to a
// neighbouring near-parallel segment beside p; the default 0 leaves the fixed gate),
// that sigma from the pose covariance
// (x forward, y left, heading): sqrt(j' C j) with j = (n.x, n.y, n.y p.x - n.x p.y), n its normal.
PredictedObject prediction(const Mat3& covariance) {
  PredictedObject p;
  InterestSegment crossing;
  crossing.id = "I1.corner.0";
  crossing.vehicle = {Vec2(8, -2), Vec2(8, 2)};
  InterestSegment edge;
  edge.id = "R1.left.0";
  edge.vehicle = {Vec2(3, 1), Vec2(10, 1)};
  p.segments = {crossing, edge};
  p.pose_covariance = covariance;
  return p;
}

std::vector<DetectedLine> detected() {
  DetectedLine beyond;
  beyond.vehicle = {Vec2(8.8, -1.5), Vec2(8.8, 1.5)};
  DetectedLine left;
  left.vehicle = {Vec2(4, 1.6), Vec2(9, 1.6)};
  return {beyond, left};
}

LineOptions widened() {
  LineOptions o;
  o.gate_sigma = 3;
  return o;
}

LineOptions fixedGate() { return LineOptions{}; }

std::vector<std::optional<std::string>> labels(const Mat3& covariance, const LineOptions& options = widened()) {
  std::vector<DetectedLine> lines = detected();
  labelLines(lines, prediction(covariance), options);
  return {lines[0].label, lines[1].label};
}

TEST(LineLabelling, WithoutCovarianceTheGateIsMaxDistance) {
  const auto l = labels(Mat3::Zero());
  EXPECT_FALSE(l[0].has_value());  // 0.8 m > 0.4 m
  EXPECT_FALSE(l[1].has_value());  // 0.6 m > 0.4 m
}

TEST(LineLabelling, AlongRoadUncertaintyWidensTheGateOfCrossingLinesOnly) {
  // sigma along 0.3 m: the crossing line's normal is (-1, 0), its sigma 0.3 m, gate 0.9 m >= 0.8 m;
  // the road edge's normal (0, 1) sees the lateral sigma 0.01 m only: gate 0.4 m < 0.6 m.
  const Mat3 along = Vec3(0.09, 1e-4, 0).asDiagonal();
  const auto l = labels(along);
  EXPECT_EQ(l[0], "I1.corner.0");
  EXPECT_FALSE(l[1].has_value());
  // sigma along 0.25 m: gate 0.75 m < 0.8 m.
  EXPECT_FALSE(labels(Vec3(0.0625, 1e-4, 0).asDiagonal())[0].has_value());
  // gate_sigma 0, the default: the fixed gate alone.
  EXPECT_FALSE(labels(along, fixedGate())[0].has_value());
}

// Where the map states an error (the prediction's map_sigma_m > 0), gate_sigma_uncertain_map (3 by
// default) takes gate_sigma's place: the default options widen the gate there and only there.
TEST(LineLabelling, OnAMapThatStatesItsErrorTheDefaultGateWidensWithTheCovariance) {
  const Mat3 along = Vec3(0.09, 1e-4, 0).asDiagonal();  // gate 0.9 m across the crossing line
  std::vector<DetectedLine> lines = detected();
  PredictedObject p = prediction(along);
  labelLines(lines, p, fixedGate());
  EXPECT_FALSE(lines[0].label.has_value());  // an exact map: the fixed 0.4 m
  p.map_sigma_m = 0.5;
  labelLines(lines, p, fixedGate());
  EXPECT_EQ(lines[0].label, "I1.corner.0");
  EXPECT_FALSE(lines[1].label.has_value());  // the road edge's gate stays 0.4 m < 0.6 m
  LineOptions off;
  off.gate_sigma_uncertain_map = 0;
  labelLines(lines, p, off);
  EXPECT_FALSE(lines[0].label.has_value());
}

TEST(LineLabelling, HeadingUncertaintyWidensTheGateWithRange) {
  // sigma heading 0.06 rad: the road edge's sigma at (4, 1.6) is 0.06 x 4 = 0.24 m, gate 0.72 m,
  // and at (9, 1.6) 0.54 m, gate 1.62 m: both ends within. The crossing line's ends at y = +-1.5 m:
  // 0.09 m, gate 0.4 m < 0.8 m.
  const auto l = labels(Vec3(0, 0, 0.0036).asDiagonal());
  EXPECT_FALSE(l[0].has_value());
  EXPECT_EQ(l[1], "R1.left.0");
  // sigma heading 0.04 rad: 0.16 m at x = 4, gate 0.48 m < 0.6 m.
  EXPECT_FALSE(labels(Vec3(0, 0, 0.0016).asDiagonal())[1].has_value());
}

// Two road edges 1.2 m apart (a narrow road's left and right), both predicted; a detected line 0.5 m
// right of the left edge (0.7 m left of the right one) with a lateral sigma of 0.3 m: 3 sigma (0.9 m)
// would take it for either edge, but each edge's wider gate stops halfway to the other (0.6 m): it is
// the left edge's (0.5 m <= 0.6 m) and not the right's (0.7 m > 0.6 m). Moved to 0.65 m from the left
// edge it is nearer the right one's (0.55 m) and becomes the right edge's. Without the right edge in
// the prediction the left's gate is the full 0.9 m.
TEST(LineLabelling, TheWiderGateStopsHalfwayToTheNeighbouringSegment) {
  InterestSegment left, right;
  left.id = "R1.left.0";
  left.vehicle = {Vec2(3, 0.6), Vec2(12, 0.6)};
  right.id = "R1.right.0";
  right.vehicle = {Vec2(3, -0.6), Vec2(12, -0.6)};
  PredictedObject p;
  p.segments = {left, right};
  p.pose_covariance = Vec3(1e-4, 0.09, 0).asDiagonal();
  const auto label = [&](double y, const PredictedObject& prediction) {
    std::vector<DetectedLine> lines(1);
    lines[0].vehicle = {Vec2(4, y), Vec2(10, y)};
    labelLines(lines, prediction, widened());
    return lines[0].label;
  };
  EXPECT_EQ(label(0.1, p), "R1.left.0");
  EXPECT_EQ(label(-0.05, p), "R1.right.0");
  PredictedObject alone = p;
  alone.segments = {left};
  EXPECT_EQ(label(-0.25, alone), "R1.left.0");   // 0.85 m <= 0.9 m
  EXPECT_FALSE(label(-0.35, alone).has_value());  // 0.95 m > 0.9 m
  // A segment beside the point only counts where it is beside it: the right edge moved beyond the
  // detected line's ends (x 14-20) leaves the left edge's gate whole.
  PredictedObject apart = p;
  apart.segments[1].vehicle = {Vec2(14, -0.6), Vec2(20, -0.6)};
  EXPECT_EQ(label(-0.25, apart), "R1.left.0");
}

TEST(LineLabelling, GateSigmaMustNotBeNegative) {
  LineOptions o;
  o.gate_sigma = -1;
  EXPECT_THROW(o.validate(), InvalidInput);
  EXPECT_NO_THROW(LineOptions{}.validate());
}

}  // namespace
}  // namespace mapnav
