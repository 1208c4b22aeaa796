// A consistent filter: the fraction of frames whose true error lies within 2 sigma of
// the filter's covariance, per axis of the road, and the mean NEES (mission/metrics.h), on
// hand-made frames with known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "mapnav/mission/metrics.h"

namespace mapnav {
namespace {

// sigma along x 0.1 m, along y 0.2 m, heading 0.01 rad.
Mat3 diagonal() { return Vec3(0.01, 0.04, 1e-4).asDiagonal(); }

FrameRecord frame(double along, double lateral, double heading, bool truth = true) {
  FrameRecord f;
  if (truth) f.truth = Pose2();
  f.error.along_m = along;
  f.error.lateral_m = lateral;
  f.error.heading_rad = heading;
  f.covariance = diagonal();
  f.road_heading_rad = 0;  // along the road is world x
  return f;
}

TEST(FilterConsistency, FractionsWithin2SigmaPerAxisAndMeanNeesOfAHandMadeRun) {
  // within 2 sigma (0.2 along, 0.4 lateral, 0.02 heading):   along  lateral  heading   NEES
  const std::vector<FrameRecord> frames = {
      frame(0.15, 0.3, 0.015),    //                              yes    yes      yes       2.25 + 2.25 + 2.25 = 6.75
      frame(0.25, 0.1, -0.03),    //                              no     yes      no        6.25 + 0.25 + 9    = 15.5
      frame(-0.19, 0.5, 0.005),   //                              yes    no       yes       3.61 + 6.25 + 0.25 = 10.11
      frame(0.0, -0.6, 0.0),      //                              yes    no       yes       9
      frame(5.0, 5.0, 1.0, false),  // no truth: not counted
  };
  MissionMetrics m;
  accumulateMetrics(frames, Route{}, m);
  EXPECT_EQ(m.consistency.frames, 4u);
  EXPECT_DOUBLE_EQ(m.consistency.within_2sigma_along, 0.75);
  EXPECT_DOUBLE_EQ(m.consistency.within_2sigma_lateral, 0.5);
  EXPECT_DOUBLE_EQ(m.consistency.within_2sigma_heading, 0.75);
  EXPECT_EQ(m.consistency.nees_frames, 4u);
  EXPECT_NEAR(m.consistency.nees_mean, (6.75 + 15.5 + 10.11 + 9.0) / 4, 1e-9);
}

TEST(FilterConsistency, TheCovarianceIsTurnedIntoTheRoadsFrame) {
  // On a road heading north, along the road is world y: sigma 0.2 m there, 0.1 m across.
  const Mat3 p = diagonal();
  PoseError e;
  e.along_m = 0.3;
  e.lateral_m = 0.15;
  const FrameConsistency north = frameConsistency(e, p, std::numbers::pi / 2);
  EXPECT_TRUE(north.along);
  EXPECT_TRUE(north.lateral);
  ASSERT_TRUE(north.nees.has_value());
  EXPECT_NEAR(*north.nees, 0.3 * 0.3 / 0.04 + 0.15 * 0.15 / 0.01, 1e-9);
  const FrameConsistency east = frameConsistency(e, p, 0.0);
  EXPECT_FALSE(east.along);   // 0.3 > 2 x 0.1
  EXPECT_TRUE(east.lateral);  // 0.15 < 2 x 0.2
  // At 45 degrees both axes see (0.01 + 0.04) / 2: sigma 0.158 m.
  const FrameConsistency diagonal_road = frameConsistency(e, p, std::numbers::pi / 4);
  EXPECT_TRUE(diagonal_road.along);  // 0.3 < 0.316
}

TEST(FilterConsistency, ASingularCovarianceHasNoNeesAndHoldsOnlyAZeroError) {
  PoseError e;
  e.along_m = 0.1;
  const FrameConsistency c = frameConsistency(e, Mat3::Zero(), 0.0);
  EXPECT_FALSE(c.along);
  EXPECT_TRUE(c.lateral);
  EXPECT_TRUE(c.heading);
  EXPECT_FALSE(c.nees.has_value());
}

}  // namespace
}  // namespace mapnav
