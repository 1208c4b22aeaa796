// Path agreement in a mission run's summary (runner.h, path_agreement.h): a replay over a log whose
// answer is known (a straight road driven on its centre line), the same log without truth (not
// measured), and the closed loop.
#include <gtest/gtest.h>

#include <cmath>

#include <nlohmann/json.hpp>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/geometry/camera_io.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/map/map_io.h"
#include "mapnav/mission/runner.h"
#include "mapnav/mission_sim/closed_loop.h"
#include "mapnav/sim/world.h"
#include "mapnav/testing/support.h"
#include "mapnav/vision/pipelines.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;

/// The minimal map's R1 runs straight from I1 (0, 0) to I2 (40, 0), 2 m wide: the mission drives it
/// from 5 m to 25 m. The campus missions' camera (it sees the ground 2.0-12.0 m ahead).
fs::path straightMission(const fs::path& dir) {
  const std::string text = R"({"format": "mapnav-mission/1", "name": "straight", "map": ")" +
                           testing::fixturePath("maps/valid/minimal.json").string() + R"(", "camera": ")" +
                           testing::mapPath("cameras/terregator_pinhole.json").string() +
                           R"(", "start": "R1@I1+5", "goal": "R1@I1+25", "speed_mps": 1.0, "frame_rate_hz": 2.0})";
  writeFileAtomic(dir / "straight.json", text);
  return dir / "straight.json";
}

constexpr std::size_t kStraightFrames = 41;  // x = 5, 5.5, ..., 25 m
constexpr double kStraightStepM = 0.5;

/// The log the answer is known for: 41 frames on R1's centre line, x = 5, 5.5, ..., 25 m, facing along
/// it, 0.5 s and 0.5 m apart, with exact odometry and (`truth`) the exact pose, rendered by the
/// simulator's world.
fs::path straightLog(const MissionFile& mission, const fs::path& dir, bool truth) {
  LogHeader header;
  header.name = "straight";
  header.camera = loadCamera(mission.camera);
  header.frame_rate_hz = mission.frame_rate_hz;
  const World world(loadMap(mission.map));
  ReplayLogWriter writer(dir, header);
  for (std::size_t i = 0; i < kStraightFrames; ++i) {
    const Pose2 pose(5.0 + kStraightStepM * static_cast<double>(i), 0.0, 0.0);
    LogFrame f;
    f.t = 0.5 * static_cast<double>(i);
    f.odometry.distance_m = i == 0 ? 0.0 : kStraightStepM;
    if (truth) f.truth = pose;
    const Frame frame = world.render(*header.camera, pose, f.t);
    writer.add(f, frame.rgb, &frame.mask);
  }
  writer.finish();
  return dir;
}

/// The share of the ground in view that the road itself (|y| <= 1 m) covers, counted on the lattice
/// of PathAgreement::ground_share (every 4th pixel of every 4th row): what a road found that is
/// exactly the road scores, the same in every frame of the straight log.
double straightRoadShare(const Camera& camera) {
  std::size_t ground = 0, road = 0;
  for (int v = 2; v < camera.height(); v += 4) {
    for (int u = 2; u < camera.width(); u += 4) {
      const auto g = camera.backproject(Vec2(u, v));
      if (!g) continue;
      ++ground;
      road += std::abs(g->y()) <= 1.0;
    }
  }
  return static_cast<double>(road) / static_cast<double>(ground);
}

class StraightRoad : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    registerBuiltinPipelines();
    dir_ = new fs::path(testing::freshTempDir());
    mission_ = new MissionFile(loadMission(straightMission(*dir_)));
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
    delete mission_;
  }
  // Replays the log `log` ("truth" or "no-truth"), rendered when a test first asks for it: ctest runs
  // each test in a process of its own, and each needs one log or none.
  static MissionRun replay(const std::string& log, const std::string& pipeline) {
    const fs::path dir = *dir_ / log;
    if (!fs::exists(dir)) straightLog(*mission_, dir, log == "truth");
    RunOptions options;
    options.pipeline = pipeline;
    return runReplay(*mission_, dir, options);
  }
  static fs::path* dir_;
  static MissionFile* mission_;
};
fs::path* StraightRoad::dir_ = nullptr;
MissionFile* StraightRoad::mission_ = nullptr;

/// Frame i has (40 − i) · 0.5 m of truth ahead: a path that reaches 7 m (min_reach_m) for i ≤ 26
/// (27 measured, 14 too short), 10 m (the direction's far end) for i ≤ 20 (21 with a direction) and
/// x = 7.5 m (the offset) for i ≤ 25 (the 25 consecutive pairs (0, 1) .. (24, 25)). Every path is in
/// view (the camera sees the ground 2.0-12.0 m ahead).
constexpr std::size_t kStraightMeasured = 27, kStraightTooShort = 14, kStraightAngleFrames = 21, kStraightOffsetPairs = 25;

void expectStraightCounts(const PathAgreementSummary& s) {
  EXPECT_EQ(s.frames, kStraightFrames);
  EXPECT_EQ(s.measured, kStraightMeasured);
  EXPECT_EQ(s.path_too_short, kStraightTooShort);
  EXPECT_EQ(s.no_truth, 0u);
  EXPECT_EQ(s.out_of_view, 0u);
  EXPECT_EQ(s.angle_frames, kStraightAngleFrames);
  EXPECT_EQ(s.offset_pairs, kStraightOffsetPairs);
}

TEST_F(StraightRoad, TheRoadFoundHoldsThePathInEveryMeasuredFrame) {
  const MissionRun run = replay("truth", "sidewalk");
  ASSERT_EQ(run.frames.size(), kStraightFrames);
  ASSERT_TRUE(run.metrics.path_agreement);
  const PathAgreementSummary& s = *run.metrics.path_agreement;
  expectStraightCounts(s);
  EXPECT_EQ(s.no_region, 0u);
  EXPECT_EQ(s.inside_goal_frames, kStraightMeasured);
  EXPECT_EQ(s.median_inside, 1.0);
  // The sidewalk pipeline gives no centre line: no angle or offset, and their goals are not counted.
  EXPECT_EQ(s.centre_line_frames, 0u);
  EXPECT_EQ(s.angle_missing, kStraightAngleFrames);
  EXPECT_FALSE(s.angle_goal_fraction);
  // The road (2 m wide) is a part of the ground in view (1.4 m wide 2 m ahead, 6.6 m wide 12 m ahead),
  // and the region found is the road.
  ASSERT_TRUE(s.median_ground_share);
  const double road_share = straightRoadShare(*loadCamera(mission_->camera));
  EXPECT_LT(road_share, 0.9);
  EXPECT_NEAR(*s.median_ground_share, road_share, 0.02);
  // Frame by frame: the path straight ahead on the centre line, every sample in view inside.
  ASSERT_EQ(run.path_agreement.size(), kStraightFrames);
  for (std::size_t i = 0; i < kStraightFrames; ++i) {
    const PathAgreement& a = run.path_agreement[i];
    if (i >= kStraightMeasured) {
      EXPECT_EQ(a.status, PathStatus::TooShort) << i;
      continue;
    }
    ASSERT_EQ(a.status, PathStatus::Measured) << i;
    EXPECT_EQ(a.inside, a.path_image.size()) << i;
    EXPECT_VEC2_NEAR(a.path.front(), Vec2(2, 0), 1e-9);
  }
  // The summary is the one `log track` prints, under the run's.
  const std::string text = summaryText(run);
  EXPECT_NE(text.find("  path agreement (the true future path 2-15 m ahead, from the log's truth):\n"
                      "    road found holds >= 95 % of the path in 27 of 27 (1.000) measured frames; median 1.000\n"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("    not measured: 14 of 41 frames (no truth 0, path too short 14, path out of view 0)"),
            std::string::npos)
      << text;
  const auto j = nlohmann::json::parse(runToJson(run));
  EXPECT_EQ(j["path_agreement"]["measured"], 27);
  EXPECT_EQ(j["path_agreement"]["unmeasured"]["path_too_short"], 14);
  EXPECT_EQ(j["path_agreement"]["inside_goal_frames"], 27);
  EXPECT_EQ(j["path_agreement"]["median_inside"], 1.0);
  EXPECT_EQ(j["path_agreement"]["median_angle_deg"], nullptr);
}

TEST_F(StraightRoad, TheCentreLineRunsAlongThePathAndItsOffsetDoesNotJump) {
  const MissionRun run = replay("truth", "cluster-perceptron");
  ASSERT_TRUE(run.metrics.path_agreement);
  const PathAgreementSummary& s = *run.metrics.path_agreement;
  expectStraightCounts(s);
  // A frame whose path is too short is not held against its detection (pathAgreement stops there).
  EXPECT_EQ(s.centre_line_frames, kStraightMeasured);
  EXPECT_EQ(s.angle_missing, 0u);
  EXPECT_EQ(s.angle_goal_frames, kStraightAngleFrames);
  ASSERT_TRUE(s.median_angle_deg);
  EXPECT_LT(*s.median_angle_deg, 0.2);
  EXPECT_EQ(s.offset_missing, 0u);
  EXPECT_EQ(s.offset_goal_pairs, kStraightOffsetPairs);
  ASSERT_TRUE(s.median_offset_jump_m);
  EXPECT_LT(*s.median_offset_jump_m, 0.02);
  EXPECT_EQ(s.inside_goal_frames, kStraightMeasured);
}

TEST_F(StraightRoad, ALogWithoutTruthHasNoPathAgreement) {
  const MissionRun run = replay("no-truth", "sidewalk");
  ASSERT_EQ(run.frames.size(), kStraightFrames);
  EXPECT_FALSE(run.metrics.has_truth);
  EXPECT_FALSE(run.metrics.path_agreement);
  EXPECT_TRUE(run.path_agreement.empty());
  const auto j = nlohmann::json::parse(runToJson(run));
  ASSERT_TRUE(j.contains("path_agreement"));
  EXPECT_TRUE(j["path_agreement"].is_null());
  const std::string text = summaryText(run);
  EXPECT_NE(text.find("no ground truth: errors and path agreement not measured"), std::string::npos) << text;
  EXPECT_EQ(text.find("path agreement ("), std::string::npos) << text;
}

TEST_F(StraightRoad, TheClosedLoopMeasuresItOnTheSimulatorsTruth) {
  RunOptions options;
  options.max_frames = 20;  // 9.5 s at 1 m/s after the start: about 9 m
  const MissionRun run = runClosedLoop(*mission_, options);
  ASSERT_EQ(run.frames.size(), 20u);
  ASSERT_TRUE(run.metrics.path_agreement);
  const PathAgreementSummary& s = *run.metrics.path_agreement;
  EXPECT_EQ(s.frames, 20u);
  // The run ends after 20 frames, and so does the truth: measured are the frames the vehicle drove
  // 7 m or more after (min_reach_m), the truth between frames taken as straight (the road is).
  // A frame that reaches 7 m to within the simulated motion's rounding (at 0.5 m a frame one does,
  // 1e-9 m short) may count either way.
  std::size_t reach7 = 0, borderline = 0;
  for (std::size_t i = 0; i < run.frames.size(); ++i) {
    double driven = 0;
    for (std::size_t j = i + 1; j < run.frames.size(); ++j)
      driven += (run.frames[j].truth->translation() - run.frames[j - 1].truth->translation()).norm();
    if (std::abs(driven - 7.0) < 1e-6) ++borderline;
    else reach7 += driven > 7.0;
  }
  EXPECT_GT(reach7, 0u);
  EXPECT_GE(s.measured, reach7);
  EXPECT_LE(s.measured, reach7 + borderline);
  EXPECT_EQ(s.measured + s.path_too_short, 20u);
  EXPECT_EQ(s.inside_goal_frames, s.measured);
  EXPECT_NE(summaryText(run).find("from the simulator's truth"), std::string::npos);
}

TEST(RunPathAgreement, BadOptionsAreNamed) {
  RunOptions options;
  options.path_agreement.step_m = 0;
  EXPECT_THROW(options.validate(), InvalidInput);
}

}  // namespace
}  // namespace mapnav
