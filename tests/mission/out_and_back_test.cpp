// Routes that revisit roads: an out-and-back via route on the campus map — from R1 10 m
// east of I1, out east to the via point R1@I1+25, back west through I1 and right onto R2 to
// R2@I1+10. The route turns around at the via point (a leg of its own, said in the dialogue), the
// Navigator's commands follow the planned legs in order, and in closed loop the vehicle stops at the
// via point, turns around in place and drives on to the goal.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "mapnav/core/io.h"
#include "mapnav/mission/modules.h"
#include "mapnav/mission/runner.h"
#include "mapnav/mission_sim/closed_loop.h"
#include "mapnav/mission_sim/simulate.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"
#include "mapnav/vision/pipelines.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;

NavigatorModule outAndBackNavigator() {
  return NavigatorModule(testing::campusMap(), parseRoadPosition("R1@I1+10"),
                         {parseRoadPosition("R1@I1+25"), parseRoadPosition("R2@I1+10")});
}

TEST(OutAndBack, TheRouteTurnsAroundAtTheViaPoint) {
  const Route route = outAndBackNavigator().route();
  EXPECT_EQ(toDialogue(route),
            "Drive on R1 15.0 m and turn around in place at R1@I1+25 onto R1.\n"
            "Drive on R1 25.0 m and turn right 90 degrees at I1 onto R2.\n"
            "Drive on R2 10.0 m.\n");
  EXPECT_NEAR(route.length_m, 50.0, 1e-9);
  EXPECT_NEAR(route.line.length(), 50.0, 1e-9);
}

CurrentPosition postedPosition(const Pose2& pose, double t) {
  CurrentPosition p;
  p.pose = pose;
  p.timestamp = t;
  return p;
}

// What a command says: its road and what comes after it ("around R1@I1+25", "right I1", "goal").
std::string commandSaid(const MotionCommand& c) {
  if (c.kind == CommandKind::Stop) return "stop";
  return c.road + " then " + (c.next_turn ? turnDirection(c.next_turn->angle) + " " + c.next_turn->at : "goal");
}

// The true path, 0.1 m a step: east on R1 to x = 74.9, a turn in place there in 10 degree steps,
// west to I1, north on R2 to y = 50. Each pose is posted as the CurrentPosition and planned from.
TEST(OutAndBack, TheCommandsFollowThePlannedLegsInOrder) {
  NavigatorModule navigator = outAndBackNavigator();
  Blackboard board;
  std::vector<Pose2> poses;
  for (double x = 60; x <= 74.9 + 1e-9; x += 0.1) poses.emplace_back(x, 40, 0);
  for (int deg = 10; deg <= 180; deg += 10) poses.emplace_back(74.9, 40, degToRad(deg));
  for (double x = 74.8; x >= 50.0 - 1e-9; x -= 0.1) poses.emplace_back(x, 40, kPi);
  for (double y = 40.1; y <= 50.0 + 1e-9; y += 0.1) poses.emplace_back(50, y, kPi / 2);
  std::vector<std::string> sequence;
  std::size_t ends_at_turn = 0;
  double t = 0;
  for (const Pose2& pose : poses) {
    board.post(Module::Map, postedPosition(pose, t));
    const MotionCommand& c = navigator.plan(board, t);
    if (sequence.empty() || sequence.back() != commandSaid(c)) sequence.push_back(commandSaid(c));
    if (c.path_ends_at_turn) {
      ++ends_at_turn;
      // The plan stops at the via point (a micrometre before it: no hair of the way back).
      EXPECT_VEC2_NEAR(c.path.back(), Vec2(75 - 1e-6, 40), 1e-9);
      EXPECT_LT(pose.x(), 75.0);
    }
    for (const Vec2& p : c.path) EXPECT_LE(p.x(), 75.0 + 1e-9);  // never a plan through the via point
    t += 0.5;
  }
  EXPECT_EQ(sequence, (std::vector<std::string>{"R1 then around R1@I1+25", "R1 then right I1", "R2 then goal"}));
  EXPECT_EQ(ends_at_turn, 148u);  // x = 60.0 .. 74.7 (74.8 is within 0.25 m: the turnaround is reached)
  EXPECT_TRUE(navigator.finished());
  EXPECT_EQ(navigator.replans(), 0u);
}

// The mission file: the campus missions' settings, sidewalk at its defaults.
fs::path outAndBackMission(const fs::path& dir) {
  writeFileAtomic(dir / "m.json", R"({"format": "mapnav-mission/1", "map": ")" + testing::mapPath("cmu_campus.json").string() +
                                      R"(", "camera": ")" + testing::mapPath("cameras/terregator_pinhole.json").string() +
                                      R"(", "start": "R1@I1+10", "via": ["R1@I1+25"], "goal": "R2@I1+10",
      "speed_mps": 0.6, "frame_rate_hz": 2.0, "vision": {"pipeline": "sidewalk"},
      "world": {"seed": 5, "shadow_density": 0.05, "noise_sigma": 2.0},
      "odometry": {"seed": 6, "scale_error": 0.01, "gyro_bias_deg_s": 0.05, "distance_sigma_m": 0.005, "heading_sigma_deg": 0.1}})");
  return dir / "m.json";
}

// The simulator's driver (replay logs) drives it stretch by stretch: 50 m, not round in circles.
TEST(OutAndBack, TheSimulatorDrivesItOnceAndReachesTheGoal) {
  const fs::path dir = testing::freshTempDir();
  const SimulateResult r = simulate(loadMission(outAndBackMission(dir)), dir / "log");
  EXPECT_TRUE(r.reached_goal);
  EXPECT_NEAR(r.route_length_m, 50.0, 1e-9);
  EXPECT_GT(r.distance_m, 49.0);
  EXPECT_LT(r.distance_m, 50.5);
}

// Closed loop at the campus missions' settings: stops within 0.25 m of the via point, turns around
// in place (the skid-steer turns on its tracks), drives back and on to the goal, never off the path.
TEST(OutAndBack, InClosedLoopTheVehicleTurnsAroundInPlaceAndReachesTheGoal) {
  registerBuiltinPipelines();
  const fs::path dir = testing::freshTempDir();
  const fs::path mission = outAndBackMission(dir);
  RunOptions options;
  options.trace = dir / "trace.jsonl";
  const MissionRun run = runClosedLoop(loadMission(mission), options);
  EXPECT_TRUE(run.metrics.reached_goal) << run.outcome;
  EXPECT_EQ(run.metrics.left_path_frames, 0u);
  EXPECT_EQ(run.metrics.replans, 0u);
  // The truth: out to within 0.25 m of x = 75, a turn there on the spot, then back west.
  double farthest = 0, turn_start_x = 0;
  bool turned_in_place = false;
  for (std::size_t i = 1; i < run.frames.size(); ++i) {
    const Pose2& a = *run.frames[i - 1].truth;
    const Pose2& b = *run.frames[i].truth;
    farthest = std::max(farthest, b.x());
    const double turned = std::abs(normalizeAngle(b.heading() - a.heading()));
    if (turned > degToRad(10) && (b.translation() - a.translation()).norm() < 1e-3) {
      turned_in_place = true;
      turn_start_x = b.x();
    }
  }
  EXPECT_TRUE(turned_in_place);
  EXPECT_GT(farthest, 74.7);
  EXPECT_LE(farthest, 75.05);
  EXPECT_NEAR(turn_start_x, farthest, 0.05);
  const std::string dialogue = traceDialogue(readFile(dir / "trace.jsonl"), "trace.jsonl");
  EXPECT_NE(dialogue.find("Navigator: Drive on R1 15.0 meters and turn around in place at road R1, 25 meters from I1."),
            std::string::npos)
      << dialogue.substr(0, 600);
  // Motion Control says the turn: "Ok. I turn in place, then drive.", from the first plan back.
  const std::size_t turn = dialogue.find("Motion Control: Ok. I turn in place, then drive.");
  ASSERT_NE(turn, std::string::npos);
  const std::size_t back = dialogue.rfind("Navigator: Drive on it 25.0 meters and turn to right 90 degrees.", turn);
  ASSERT_NE(back, std::string::npos);
  EXPECT_LT(dialogue.rfind("turn around in place", turn), back);
}

}  // namespace
}  // namespace mapnav
