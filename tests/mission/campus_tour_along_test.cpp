// The along-road bar on the campus: campus_tour (430 m round the campus, nine intersections) in closed
// loop at the mission's settings, with the campus's landmarks and the ground's step: the along-road
// error within 0.10 m and its RMS within 0.04 m over the whole run, lateral and heading as the
// missions hold them (before the landmarks and the step: along max 0.53 m, RMS 0.13 m).
#include <gtest/gtest.h>

#include <cstdio>

#include "mapnav/mission/mission_file.h"
#include "mapnav/mission/runner.h"
#include "mapnav/mission_sim/closed_loop.h"
#include "mapnav/testing/support.h"
#include "mapnav/vision/pipelines.h"

namespace mapnav {
namespace {

TEST(CampusTour, TheAlongRoadErrorStaysWithinTenCentimetresOverTheWholeTour) {
  registerBuiltinPipelines();
  const MissionRun run = runClosedLoop(loadMission(testing::mapPath("missions/campus_tour.json")));
  const MissionMetrics& m = run.metrics;
  std::printf("campus_tour: along max %.3f m, RMS %.3f m; lateral RMS %.4f m, heading RMS %.3f deg; %zu of %zu frames "
              "with the ground's step; odometry scale %.4f\n",
              m.estimate.along_max_m, m.estimate.along_rms_m, m.estimate.lateral_rms_m, m.estimate.heading_rms_deg,
              m.ground_steps_used, m.frames, run.odometry_scale);
  EXPECT_TRUE(m.reached_goal) << run.outcome;
  EXPECT_TRUE(m.stayedOnPath());
  EXPECT_LE(m.estimate.along_max_m, 0.10);
  EXPECT_LE(m.estimate.along_rms_m, 0.04);
  EXPECT_LE(m.estimate.lateral_rms_m, 0.02);
  EXPECT_LE(m.estimate.heading_rms_deg, 0.2);
  EXPECT_GT(m.odometry_only.along_max_m, 2.0);  // what the odometry alone does
  EXPECT_NEAR(run.odometry_scale, 1 / 1.015, 0.002);  // the encoders read 1.5 % long
}

}  // namespace
}  // namespace mapnav
