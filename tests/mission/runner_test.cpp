// The mission runner end to end on simulated logs: replay meets the targets and is
// deterministic, a black frame halts and the mission resumes or ends as configured, the closed
// loop reaches the goal, and the trace reads back as the paper's dialogue.
#include "mapnav/mission/runner.h"

#include <cmath>
#include <cstdlib>
#include <optional>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/core/strprintf.h"
#include "mapnav/image/png.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/map/map_io.h"
#include "mapnav/mission/trace.h"
#include "mapnav/mission_sim/closed_loop.h"
#include "mapnav/mission_sim/simulate.h"
#include "mapnav/navigator/road_position.h"
#include "mapnav/sim/map_error.h"
#include "mapnav/testing/support.h"
#include "mapnav/vision/pipelines.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;

MissionFile shortCrossing() { return loadMission(testing::fixturePath("missions/short_crossing.json")); }

// One simulated log of the short crossing, shared by the tests of this suite: under ctest the one
// the fixture MissionFixture.SimulateShortCrossingLog wrote with `mapnav simulate` (each ctest test is
// a process of its own; tests/mission/CMakeLists.txt), read only; run by hand, simulated here.
class ReplayShortCrossing : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    registerBuiltinPipelines();
    dir_ = new fs::path(fs::temp_directory_path() / ("mapnav-runner-test-" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    const char* made = std::getenv("MAPNAV_SHORT_CROSSING_LOG");
    log_ = new fs::path(made != nullptr ? fs::path(made) : *dir_ / "log");
    if (made != nullptr) {
      ASSERT_TRUE(fs::is_regular_file(*log_ / "frames.jsonl")) << "the fixture's log " << *log_ << " is missing";
    } else {
      const SimulateResult r = simulate(shortCrossing(), *log_);
      ASSERT_TRUE(r.reached_goal);
    }
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
    delete log_;
  }
  static fs::path log() { return *log_; }
  static fs::path dir() { return *dir_; }
  static fs::path* dir_;
  static fs::path* log_;
};
fs::path* ReplayShortCrossing::dir_ = nullptr;
fs::path* ReplayShortCrossing::log_ = nullptr;

TEST_F(ReplayShortCrossing, ReachesTheGoalWithTheTargetsWhileOdometryAloneDrifts) {
  const MissionRun run = runReplay(shortCrossing(), log());
  const MissionMetrics& m = run.metrics;
  EXPECT_EQ(run.mode, "replay");
  EXPECT_EQ(run.pipeline, "sidewalk");
  EXPECT_TRUE(m.reached_goal) << run.outcome;
  EXPECT_TRUE(m.has_truth);
  EXPECT_EQ(m.frames, run.frames.size());
  EXPECT_GT(m.frames, 40u);
  EXPECT_LE(m.estimate.lateral_rms_m, 0.05);
  EXPECT_LE(m.estimate.heading_rms_deg, 0.5);
  EXPECT_LE(m.along_after_intersection_max_m, 0.15);
  EXPECT_EQ(m.intersections_checked, 1u);
  EXPECT_GT(m.odometry_only.max_error_m, m.estimate.max_error_m);
  EXPECT_EQ(m.vision_failures, 0u);
  EXPECT_EQ(m.replans, 0u);
  EXPECT_GT(m.latency_ms_median, 0.0);
  EXPECT_GE(m.latency_ms_p99, m.latency_ms_median);
  // Every frame has its record, with the truth and a correction.
  std::size_t corrected = 0;
  for (const FrameRecord& f : run.frames) {
    ASSERT_TRUE(f.truth);
    corrected += f.status == PositionStatus::Corrected ? 1 : 0;
  }
  EXPECT_GT(corrected, run.frames.size() * 9 / 10);
  // The JSON has the summary's figures.
  const auto json = nlohmann::json::parse(runToJson(run));
  for (const char* key : {"frames", "reached_goal", "lateral_rms_m", "along_rms_m", "heading_rms_deg", "max_error_m",
                          "odometry_only_max_error_m", "vision_failures", "replans", "latency_ms_median",
                          "latency_ms_p99", "along_after_intersection_max_m"}) {
    EXPECT_TRUE(json.contains(key)) << key;
  }
  EXPECT_EQ(json["frames"], m.frames);
  EXPECT_NE(summaryText(run).find("odometry alone"), std::string::npos);
}

// The log's recorded path ends at the goal whatever the estimate does, so replay judges the vehicle
// where it was when the Navigator believed it arrived. An estimate pushed 3 m ahead late in the run
// (the filter does not know) makes the Navigator arrive early: not the goal reached, though the
// log's last truth is at the goal. Pushed 2 m back, the Navigator never arrives. (Integrity's
// departure test, which would put such an estimate back on odometry, is off.)
TEST_F(ReplayShortCrossing, TheGoalIsJudgedWhereTheNavigatorArrivedNotAtTheLogsEnd) {
  RunOptions ahead;
  ahead.map.integrity.departure_probability = 1;
  ahead.displace = EstimateDisplacement{40, 3.0, 0.0};
  const MissionRun early = runReplay(shortCrossing(), log(), ahead);
  const MissionMetrics& m = early.metrics;
  ASSERT_TRUE(m.arrived_frame.has_value()) << early.outcome;
  const FrameRecord& arrival = early.frames.at(*m.arrived_frame);
  ASSERT_TRUE(arrival.arrived && arrival.truth);
  EXPECT_FALSE(early.frames.at(*m.arrived_frame - 1).arrived);  // the first such frame
  EXPECT_LT(*m.arrived_frame + 5, early.frames.size());
  const double truth_then = (arrival.truth->translation() - early.goal.translation()).norm();
  EXPECT_DOUBLE_EQ(m.goal_distance_m, truth_then);
  EXPECT_GT(truth_then, 2.0);
  ASSERT_TRUE(early.frames.back().truth);
  EXPECT_LT((early.frames.back().truth->translation() - early.goal.translation()).norm(), 0.5);  // the log's end
  EXPECT_FALSE(m.reached_goal);
  EXPECT_EQ(early.outcome, strprintf("the Navigator believed it arrived at frame %zu, but the vehicle was %.2f m from the goal",
                                     *m.arrived_frame, truth_then));
  const auto json = nlohmann::json::parse(runToJson(early));
  EXPECT_EQ(json["arrived_frame"], *m.arrived_frame);
  EXPECT_EQ(json["reached_goal"], false);

  RunOptions behind;
  behind.map.integrity.departure_probability = 1;
  behind.displace = EstimateDisplacement{50, -2.0, 0.0};
  const MissionRun late = runReplay(shortCrossing(), log(), behind);
  EXPECT_FALSE(late.metrics.arrived_frame.has_value());
  EXPECT_FALSE(late.metrics.reached_goal);
  EXPECT_NEAR(late.metrics.estimate_goal_distance_m,
              (late.frames.back().estimate.translation() - late.goal.translation()).norm(), 1e-12);
  EXPECT_GT(late.metrics.estimate_goal_distance_m, 1.0);
  EXPECT_EQ(late.outcome.rfind("the log ended before the Navigator arrived: the estimate ", 0), 0u) << late.outcome;
  EXPECT_TRUE(nlohmann::json::parse(runToJson(late))["arrived_frame"].is_null());
}

TEST_F(ReplayShortCrossing, ReplayingTheSameLogTwiceGivesByteIdenticalTraces) {
  RunOptions options;
  options.trace = dir() / "a.jsonl";
  runReplay(shortCrossing(), log(), options);
  options.trace = dir() / "b.jsonl";
  runReplay(shortCrossing(), log(), options);
  const std::string a = readFile(dir() / "a.jsonl"), b = readFile(dir() / "b.jsonl");
  EXPECT_GT(a.size(), 10000u);
  EXPECT_EQ(a, b);
  // One line per token, framed by the mission, the route, the frames and the summary.
  EXPECT_EQ(a.rfind("{\"t\":0.0,\"frame\":null,\"module\":\"User\",\"type\":\"Mission\"", 0), 0u);
  EXPECT_EQ(testing::occurrences(a, "\"type\":\"Frame\""), testing::occurrences(a, "\"type\":\"PredictedObject\""));
  EXPECT_EQ(testing::occurrences(a, "\"type\":\"Frame\""), testing::occurrences(a, "\"type\":\"CurrentPosition\""));
  EXPECT_EQ(testing::occurrences(a, "\"type\":\"Frame\""), testing::occurrences(a, "\"type\":\"MotionCommand\""));
  EXPECT_EQ(testing::occurrences(a, "\"type\":\"Summary\""), 1u);
  EXPECT_EQ(testing::occurrences(a, "\"latency"), 0u);  // wall-clock figures stay out of the trace
}

TEST_F(ReplayShortCrossing, TheTracesSummaryHasTheRunsFilterConsistency) {
  RunOptions options;
  options.trace = dir() / "c.jsonl";
  options.max_frames = 20;
  const MissionRun run = runReplay(shortCrossing(), log(), options);
  const std::string text = readFile(options.trace);
  const auto last = nlohmann::json::parse(text.substr(text.rfind("\n{") + 1));
  ASSERT_EQ(last["type"], "Summary");
  const FilterConsistency& c = run.metrics.consistency;
  ASSERT_EQ(c.frames, 20u);
  const auto& j = last["payload"]["consistency"];
  EXPECT_NEAR(j["within_2sigma_along"].get<double>(), c.within_2sigma_along, 1e-4);
  EXPECT_NEAR(j["within_2sigma_lateral"].get<double>(), c.within_2sigma_lateral, 1e-4);
  EXPECT_NEAR(j["within_2sigma_heading"].get<double>(), c.within_2sigma_heading, 1e-4);
  EXPECT_NEAR(j["nees_mean"].get<double>(), c.nees_mean, 0.01);
}

TEST_F(ReplayShortCrossing, TheTraceReadsBackAsThePapersDialogue) {
  RunOptions options;
  options.trace = dir() / "dialogue.jsonl";
  options.max_frames = 12;
  const MissionRun run = runReplay(shortCrossing(), log(), options);
  EXPECT_TRUE(run.stopped_early);
  const std::string text = traceDialogue(readFile(options.trace), options.trace.string());
  EXPECT_EQ(text.rfind("User: Robot is at road R2, 30 meters from I1.\n      Navigate to road R4, 6 meters from I2.", 0), 0u)
      << text.substr(0, 300);
  EXPECT_NE(text.find("Navigator: Route planned, 16.0 m: Drive on R2 10.0 m and go straight through I2 onto R4."),
            std::string::npos);
  EXPECT_NE(text.find("Map: Vision will see straight road (R19, R2, R4, R9) and cross intersection (I2). The color on the "
                      "left and on the right is grass. Detect them."),
            std::string::npos)
      << text.substr(0, 1500);
  EXPECT_NE(text.find("Vision: Ok. I found them."), std::string::npos);
  EXPECT_NE(text.find("Navigator: Drive on R2 10.0 meters and go straight through I2."), std::string::npos)
      << text.substr(0, 1500);
  EXPECT_NE(text.find("Navigator: Drive on it "), std::string::npos);
  EXPECT_NE(text.find("Motion Control: Ok. (replay: recorded, not driven)"), std::string::npos);
  EXPECT_NE(text.find("Map: You are at ("), std::string::npos);
  EXPECT_NE(text.find("[frame 11, 5.5 s]"), std::string::npos);
  EXPECT_NE(text.find("Mission: stopped after 12 frames"), std::string::npos);
}

// A copy of the log with frame `index` black.
fs::path blackOut(const fs::path& log, const fs::path& copy, std::size_t index) {
  fs::copy(log, copy, fs::copy_options::recursive);
  char name[32];
  std::snprintf(name, sizeof name, "images/%06zu.png", index);
  const Image original = readPng(copy / name);
  writePng(Image(original.width, original.height, 3), copy / name);
  return copy;
}

TEST_F(ReplayShortCrossing, ABlackFrameHaltsAndTheMissionResumesAfterTheConfiguredFrames) {
  const fs::path log_copy = blackOut(log(), dir() / "black", 20);
  MissionFile mission = shortCrossing();
  mission.halt.resume_after_frames = 2;
  RunOptions options;
  options.trace = dir() / "black.jsonl";
  const MissionRun run = runReplay(mission, log_copy, options);
  EXPECT_EQ(run.metrics.vision_failures, 1u);
  EXPECT_EQ(run.metrics.halts, 1u);
  EXPECT_FALSE(run.ended_by_halt);
  EXPECT_FALSE(run.frames[20].vision_ok);
  EXPECT_NE(run.frames[20].vision_reason.find("dark"), std::string::npos) << run.frames[20].vision_reason;
  EXPECT_EQ(run.frames[20].status, PositionStatus::OdometryOnly);
  // Halted for the failing frame and two more; the Navigator says stop meanwhile.
  for (std::size_t i : {20u, 21u, 22u}) {
    EXPECT_TRUE(run.frames[i].halted) << i;
    EXPECT_EQ(run.frames[i].command, CommandKind::Stop) << i;
  }
  EXPECT_FALSE(run.frames[23].halted);
  EXPECT_EQ(run.frames[23].command, CommandKind::Drive);
  EXPECT_TRUE(run.metrics.reached_goal) << run.outcome;
  const std::string trace = readFile(options.trace);
  EXPECT_EQ(testing::occurrences(trace, "\"type\":\"VisionFailure\""), 1u);
  EXPECT_EQ(testing::occurrences(trace, "\"type\":\"Halt\""), 1u);
  EXPECT_EQ(testing::occurrences(trace, "\"type\":\"Resume\""), 1u);
  EXPECT_NE(trace.find("{\"t\":11.5,\"frame\":23,\"module\":\"User\",\"type\":\"Resume\",\"payload\":{\"frames_halted\":3}}"),
            std::string::npos);
  const std::string text = traceDialogue(trace, "black.jsonl");
  EXPECT_NE(text.find("Vision: I cannot find it: frame too dark."), std::string::npos);
  EXPECT_NE(text.find("Vision: I halt (vision failed: frame too dark). Control passes to the operator"), std::string::npos);
  EXPECT_NE(text.find("User: I hand control back (after 3 frames halted)."), std::string::npos);
}

TEST_F(ReplayShortCrossing, ABlackFrameEndsTheMissionWhenNothingResumesIt) {
  const fs::path log_copy = blackOut(log(), dir() / "black-end", 20);
  MissionFile mission = shortCrossing();
  mission.halt.resume_after_frames.reset();
  RunOptions options;
  options.trace = dir() / "black-end.jsonl";
  const MissionRun run = runReplay(mission, log_copy, options);
  EXPECT_TRUE(run.ended_by_halt);
  EXPECT_FALSE(run.metrics.reached_goal);
  EXPECT_EQ(run.frames.size(), 21u);
  EXPECT_NE(run.outcome.find("halted at frame 20"), std::string::npos) << run.outcome;
  const std::string trace = readFile(options.trace);
  EXPECT_EQ(testing::occurrences(trace, "\"type\":\"Halt\""), 1u);
  EXPECT_NE(trace.find("\"resume_after_frames\":null"), std::string::npos);
  EXPECT_NE(trace.find("\"ended_by_halt\":true"), std::string::npos);
  EXPECT_NE(traceDialogue(trace, "x").find("and the mission ends"), std::string::npos);
}

TEST_F(ReplayShortCrossing, ALogWithoutTruthIsLocalisedButNotScored) {
  const fs::path copy = dir() / "no-truth";
  fs::copy(log(), copy, fs::copy_options::recursive);
  std::string lines = readFile(copy / "frames.jsonl"), stripped;
  for (std::size_t at = 0; at < lines.size();) {
    const std::size_t end = lines.find('\n', at);
    std::string line = lines.substr(at, end - at);
    const std::size_t truth = line.find(",\"truth\":{");
    if (truth != std::string::npos) line.erase(truth, line.find('}', truth) - truth + 1);
    stripped += line + "\n";
    at = end == std::string::npos ? lines.size() : end + 1;
  }
  writeFileAtomic(copy / "frames.jsonl", stripped);
  const MissionRun run = runReplay(shortCrossing(), copy);
  EXPECT_FALSE(run.metrics.has_truth);
  EXPECT_TRUE(run.metrics.reached_goal) << run.outcome;  // by the estimate
  EXPECT_FALSE(run.frames.front().truth);
  const auto json = nlohmann::json::parse(runToJson(run));
  EXPECT_TRUE(json["lateral_rms_m"].is_null());
  EXPECT_TRUE(json["along_after_intersection_max_m"].is_null());
  EXPECT_NE(summaryText(run).find("no ground truth"), std::string::npos);
}

TEST_F(ReplayShortCrossing, AnotherPipelineByNameAndAnUnknownOne) {
  RunOptions options;
  options.max_frames = 3;
  options.pipeline = "color-rgb";
  EXPECT_EQ(runReplay(shortCrossing(), log(), options).pipeline, "color-rgb");
  options.pipeline = "no-such-pipeline";
  EXPECT_THROW(runReplay(shortCrossing(), log(), options), NotFound);
  EXPECT_THROW(runReplay(shortCrossing(), dir() / "no-log"), IoError);
}

TEST(RunnerClosedLoop, TheShortCrossingReachesTheGoalSteeringOnTheEstimate) {
  registerBuiltinPipelines();
  const fs::path dir = testing::freshTempDir();
  RunOptions options;
  options.trace = dir / "run.jsonl";
  std::size_t images = 0;
  options.on_frame = [&](const FrameView& f) { images += f.rgb->width == 512 ? 1 : 0; };
  std::size_t progress_calls = 0;
  options.progress = [&](const RunProgress& p) {
    ++progress_calls;
    EXPECT_LE(p.frame, p.total);
  };
  const MissionRun run = runClosedLoop(shortCrossing(), options);
  EXPECT_EQ(run.mode, "closed-loop");
  EXPECT_TRUE(run.metrics.reached_goal) << run.outcome;
  EXPECT_LE(run.metrics.goal_distance_m, 0.5);
  EXPECT_LE(run.metrics.estimate.lateral_rms_m, 0.05);
  EXPECT_LE(run.metrics.estimate.heading_rms_deg, 0.5);
  EXPECT_EQ(images, run.frames.size());
  EXPECT_EQ(progress_calls, run.frames.size());
  const std::string trace = readFile(options.trace);
  EXPECT_NE(trace.find("\"mode\":\"closed-loop\""), std::string::npos);
  EXPECT_NE(traceDialogue(trace, "run.jsonl").find("Motion Control: Ok. I drive."), std::string::npos);
  // Closed loop is deterministic too.
  RunOptions again;
  again.trace = dir / "run2.jsonl";
  runClosedLoop(shortCrossing(), again);
  EXPECT_EQ(readFile(again.trace), trace);
}

// A start with a lateral offset (a car's lane, `ROAD@NODE+M/LATERAL`) is where the estimate and,
// closed loop, the vehicle start: not the road's centre line.
TEST(RunnerClosedLoop, TheStartsLateralOffsetIsWhereTheEstimateAndTheVehicleStart) {
  registerBuiltinPipelines();
  MissionFile mission = shortCrossing();
  mission.start.lateral = 0.4;
  const Map map = loadMap(mission.map);
  RoadPosition centre = mission.start;
  centre.lateral = 0;
  const Vec2 beside = toPose(map, mission.start).translation();
  EXPECT_NEAR((beside - toPose(map, centre).translation()).norm(), 0.4, 1e-9);  // 0.4 m off the centre line
  RunOptions options;
  options.max_frames = 1;
  const MissionRun run = runClosedLoop(mission, options);
  // There, heading the way the route leaves the start.
  EXPECT_POSE_NEAR(run.start, Pose2(beside, run.route.line.headingAt(0)), 1e-9);
  ASSERT_EQ(run.frames.size(), 1u);
  ASSERT_TRUE(run.frames[0].truth);
  EXPECT_LT((run.frames[0].truth->translation() - beside).norm(), 0.05);  // the vehicle, one frame on
  EXPECT_LT((run.frames[0].odometry_only.translation() - beside).norm(), 0.05);
}

// A world that differs from its map: with a correlation length far beyond the campus the field is a
// near-uniform shift of the world (here, of the first seed that shifts the start by more than 0.5 m
// across the road).
// The vehicle starts at the start's place in the world and steers by the map; it drives on the
// world's roads (judged against them, it never leaves the path, while the map's centre lines lie
// the shift away from its track) and stops at the goal's place in the world. The trace gives each
// frame's truth on the map too: the true pose less the shift.
TEST(RunnerClosedLoop, AWorldThatDiffersFromItsMapIsDrivenOnItsOwnRoadsAndJudgedAgainstThem) {
  registerBuiltinPipelines();
  MissionFile mission = shortCrossing();
  const Map map = loadMap(mission.map);
  MapErrorOptions error;
  error.offset_sigma_m = 0.6;
  error.offset_length_m = 1e5;
  const Pose2 at = toPose(map, mission.start);
  const Vec2 start = at.translation(), left = leftNormal(unitVector(at.heading()));
  for (error.seed = 1; std::abs(left.dot(MapErrorField(error).offset(start))) <= 0.5; ++error.seed) {
  }
  const Vec2 shift = MapErrorField(error).offset(start);
  mission.world_json = strprintf(R"({"seed": 1985, "shadow_density": 0.05, "map_error": {"offset_sigma_m": 0.6, )"
                                 R"("offset_length_m": 1e5, "seed": %llu}})",
                                 static_cast<unsigned long long>(error.seed));
  RunOptions options;
  options.trace = testing::freshTempDir() / "run.jsonl";
  const MissionRun run = runClosedLoop(mission, options);
  ASSERT_FALSE(run.frames.empty());
  ASSERT_TRUE(run.frames.front().truth);
  EXPECT_LT((run.frames.front().truth->translation() - (start + shift)).norm(), 0.05);
  std::size_t frames = 0;
  std::istringstream text(readFile(options.trace));
  for (std::string row; std::getline(text, row);) {
    const nlohmann::json line = nlohmann::json::parse(row);
    if (line["type"] != "Frame") continue;
    const nlohmann::json& p = line["payload"];
    const Vec2 truth(p["truth"]["x"].get<double>(), p["truth"]["y"].get<double>());
    const Vec2 on_map(p["truth_on_map"]["x"].get<double>(), p["truth_on_map"]["y"].get<double>());
    EXPECT_LT((on_map - (truth - shift)).norm(), 2e-3) << "frame " << frames;  // the field varies by ~1e-5 m/m
    EXPECT_NEAR(p["truth_on_map"]["heading_deg"].get<double>(), p["truth"]["heading_deg"].get<double>(), 0.01);
    ++frames;
  }
  EXPECT_EQ(frames, run.frames.size());
  EXPECT_TRUE(run.metrics.reached_goal) << run.outcome;
  const Vec2 world_goal = toPose(map, mission.goal).translation() + MapErrorField(error).offset(start);
  EXPECT_LT((run.frames.back().truth->translation() - world_goal).norm(), 0.5);
  EXPECT_EQ(run.metrics.left_path_frames, 0u);
  EXPECT_LT(run.metrics.max_offset_from_centre_m, 0.4);
  // Against the map's roads the same track is off by about the shift across them.
  double off_map = 0;
  for (const FrameRecord& f : run.frames) off_map += pathOffset(map, f.truth->translation(), 0).offset_m;
  EXPECT_GT(off_map / run.frames.size(), 0.3) << "shift " << shift.transpose();
}

// A receiver on the simulated vehicle (the world's `gnss`): every frame of the closed loop carries a
// fix with the receiver's stated sigma (sqrt(1^2 + 1.5^2)); with the mission's use_gnss the Map fuses
// them and the mission still reaches its goal; `mapnav simulate` writes the same fixes into its log.
TEST(RunnerClosedLoop, TheSimulatedReceiversFixesAreInEveryFrameAndFused) {
  registerBuiltinPipelines();
  MissionFile mission = shortCrossing();
  mission.world_json = R"({"seed": 1985, "shadow_density": 0.05, "gnss": {"sigma_m": 1, "bias_sigma_m": 1.5, "seed": 5}})";
  mission.use_gnss = true;
  const fs::path dir = testing::freshTempDir();
  RunOptions options;
  options.trace = dir / "run.jsonl";
  const MissionRun run = runClosedLoop(mission, options);
  ASSERT_FALSE(run.frames.empty());
  const std::string trace = readFile(options.trace);
  std::size_t fused = 0;
  for (std::size_t at = trace.find("GNSS fix fused"); at != std::string::npos; at = trace.find("GNSS fix fused", at + 1)) ++fused;
  EXPECT_GE(fused, run.frames.size() / 2) << "of " << run.frames.size() << " frames";
  double sum_sq = 0;
  for (const FrameRecord& f : run.frames) {
    ASSERT_TRUE(f.gnss) << "frame " << f.index;
    EXPECT_NEAR(f.gnss_sigma_m, std::sqrt(1.0 + 2.25), 1e-9);
    sum_sq += (*f.gnss - f.truth->translation()).squaredNorm();
  }
  // 2 axes of 1.8 m: a mean square of 2 x 3.25 m^2 over many fixes; here one bias draw dominates.
  EXPECT_GT(sum_sq / run.frames.size(), 0.01);
  EXPECT_TRUE(run.metrics.reached_goal) << run.outcome;
  SimulateOptions three;
  three.max_frames = 3;
  simulate(mission, dir / "log", three);
  const ReplayLog log = ReplayLog::open(dir / "log");
  ASSERT_EQ(log.frames().size(), 3u);
  for (const LogFrame& f : log.frames()) {
    ASSERT_TRUE(f.gnss);
    EXPECT_NEAR(f.gnss->sigma_m, std::sqrt(3.25), 1e-9);
  }
}

// Integrity at the defaults: the same jump (1.5 m ahead, 0.8 m right, the filter does not know) is
// where odometry says the vehicle cannot be. On the frame of the jump the Map says the estimate
// departed, puts it back on the dead reckoning (within a few centimetres of the truth: the jump is
// undone) and the vehicle stops for that frame; the mission goes on to its goal on the path.
TEST(RunnerIntegrity, ADisplacedEstimateIsFoundDepartedOnTheFrameOfTheJumpAndPutBack) {
  registerBuiltinPipelines();
  RunOptions options;
  options.displace = EstimateDisplacement{6, 1.5, -0.8};
  const MissionRun run = runClosedLoop(shortCrossing(), options);
  ASSERT_GT(run.frames.size(), 8u);
  std::size_t departed = 0;
  for (const FrameRecord& f : run.frames) departed += f.departed ? 1 : 0;
  EXPECT_EQ(departed, 1u);
  EXPECT_EQ(run.metrics.departures, 1u);
  const FrameRecord& jumped = run.frames[6];
  EXPECT_TRUE(jumped.departed);
  EXPECT_EQ(jumped.status, PositionStatus::Lost);
  EXPECT_EQ(jumped.command, CommandKind::Stop);
  ASSERT_TRUE(jumped.truth);
  EXPECT_LT(jumped.error.distance_m, 0.1);  // back on odometry, not 1.7 m off
  EXPECT_TRUE(run.metrics.reached_goal) << run.outcome;
  EXPECT_EQ(run.metrics.left_path_frames, 0u);
  EXPECT_NE(summaryText(run).find("the estimate departed from odometry 1 times"), std::string::npos) << summaryText(run);
  const auto json = nlohmann::json::parse(runToJson(run));
  EXPECT_EQ(json["departures"], 1);
}

// The campus map with R4 drawn wrong: the world's R4 leaves I2 `degrees` right of the map's (turned
// about I2, its landmarks with it; I4 and the first points of R5 and R6 moved to its new end),
// written as a map file in `dir`.
fs::path campusWithR4Turned(const fs::path& map_file, double degrees, const fs::path& dir) {
  nlohmann::json map = nlohmann::json::parse(readFile(map_file));
  const Vec2 i2(50, 80);
  const double a = -degToRad(degrees);
  const auto turned = [&](nlohmann::json& p) {
    const Vec2 d = Vec2(p[0].get<double>(), p[1].get<double>()) - i2;
    p = {i2.x() + std::cos(a) * d.x() - std::sin(a) * d.y(), i2.y() + std::sin(a) * d.x() + std::cos(a) * d.y()};
  };
  nlohmann::json end;
  for (nlohmann::json& road : map["roads"]) {
    if (road["id"] == "R4") {
      for (nlohmann::json& p : road["centerline"]) turned(p);
      end = road["centerline"].back();
    }
  }
  for (nlohmann::json& road : map["roads"])
    if (road["from"] == "I4") road["centerline"][0] = end;
  for (nlohmann::json& i : map["intersections"])
    if (i["id"] == "I4") i["position"] = end;
  for (nlohmann::json& l : map["landmarks"])
    if (l.value("road", "") == "R4") turned(l["position"]);
  const fs::path out = dir / "campus_r4_turned.json";
  writeFileAtomic(out, map.dump());
  return out;
}

bool flagged(const FrameRecord& f) { return f.position_uncertain || f.departed || f.status == PositionStatus::Lost; }

// A wrong map road: the world's R4 runs 8 degrees right of the road the map draws (0.4 m off 3 m
// past I2, 1.4 m at the goal, 10 m on), and the map claims to be exact. The camera sees R4 from
// the start, 10 m before I2: the lines of its edges disagree with the map's, and the Map module
// says the position is uncertain before the vehicle gets there (in the run measured: from 6 m
// before I2 until the filter has turned its heading onto the world's road) instead of steering on
// in silence; the vehicle keeps to the world's road. With the world drawn from the map file itself
// (world.map naming the mission's map) the same run flags nothing.
TEST(RunnerIntegrity, AWrongMapRoadIsFlaggedBeforeTheVehicleDrivesOntoIt) {
  registerBuiltinPipelines();
  MissionFile mission = shortCrossing();
  mission.world_map = mission.map;
  const MissionRun exact = runClosedLoop(mission);
  for (const FrameRecord& f : exact.frames) EXPECT_FALSE(flagged(f)) << "frame " << f.index;
  EXPECT_TRUE(exact.metrics.reached_goal) << exact.outcome;

  mission.world_map = campusWithR4Turned(mission.map, 8, testing::freshTempDir());
  const MissionRun run = runClosedLoop(mission);
  ASSERT_FALSE(run.frames.empty());
  std::optional<std::size_t> on_r4, first_flag;
  for (const FrameRecord& f : run.frames) {
    ASSERT_TRUE(f.truth);
    if (!on_r4 && f.truth->translation().y() > 80) on_r4 = f.index;
    if (!first_flag && flagged(f)) first_flag = f.index;
  }
  ASSERT_TRUE(on_r4) << "the vehicle never passed I2";
  ASSERT_TRUE(first_flag) << "no frame flagged on a road 8 degrees off its map";
  EXPECT_LT(*first_flag, *on_r4) << "on R4 from frame " << *on_r4;
  EXPECT_GE(run.metrics.uncertain_frames + run.metrics.lost_frames, 4u);
  EXPECT_EQ(run.metrics.left_path_frames, 0u);
  EXPECT_TRUE(run.metrics.reached_goal) << run.outcome;
}

// Recovery: mid-mission the estimate jumps 1.5 m ahead and 0.8 m right of the truth
// (RunOptions::displace: the filter does not know). The Map sees Vision's road disagree with the map
// seen from the estimate, says the position is lost (the Navigator stops), finds the pose that
// explains the road on the frame after, the vehicle standing, and the mission goes on to its goal
// without leaving the path. (Integrity's departure test, which finds the same jump against
// odometry — RunnerIntegrity below — is off, to see the search.)
TEST(RunnerRecovery, ADisplacedEstimateStopsReLocalisesAndFinishes) {
  registerBuiltinPipelines();
  RunOptions options;
  options.map.integrity.departure_probability = 1;
  options.displace = EstimateDisplacement{6, 1.5, -0.8};
  options.trace = testing::freshTempDir() / "run.jsonl";
  const MissionRun run = runClosedLoop(shortCrossing(), options);
  ASSERT_GT(run.frames.size(), 8u);
  const FrameRecord& jumped = run.frames[6];
  ASSERT_TRUE(jumped.truth);
  EXPECT_NEAR(jumped.error.distance_m, std::hypot(1.5, 0.8), 0.1);  // the fault as injected
  std::size_t lost = 0, first_lost = run.frames.size();
  for (const FrameRecord& f : run.frames) {
    if (f.status != PositionStatus::Lost) continue;
    ++lost;
    first_lost = std::min(first_lost, f.index);
    EXPECT_EQ(f.command, CommandKind::Stop) << "frame " << f.index;
  }
  EXPECT_EQ(first_lost, 6u);  // seen on the frame of the jump
  EXPECT_GE(lost, 1u);
  EXPECT_EQ(run.metrics.lost_frames, lost);
  EXPECT_EQ(run.metrics.relocalisations, 1u);
  // Re-localised: the frame after the last lost one is within a grid step of the truth.
  const FrameRecord& after = run.frames[first_lost + lost];
  EXPECT_LT(after.error.distance_m, 0.25) << "frame " << after.index;
  EXPECT_TRUE(run.metrics.reached_goal) << run.outcome;
  EXPECT_EQ(run.metrics.left_path_frames, 0u);
  EXPECT_EQ(run.metrics.vision_failures, 0u);
  // The dialogue says it: lost, the Navigator's stop, the re-localisation.
  const std::string dialogue = traceDialogue(readFile(options.trace), "run.jsonl");
  EXPECT_NE(dialogue.find("I am lost (position lost: a winner to confirm on the next frame: best IoU"), std::string::npos)
      << dialogue;
  EXPECT_NE(dialogue.find("Navigator: Stop. (position lost"), std::string::npos);
  EXPECT_NE(dialogue.find("; re-localised: best IoU"), std::string::npos);
  // Without the search the same fault is not found: no line is labelled through the 0.4 m gate, the
  // vehicle steers on the wrong estimate, leaves the path and stops short of the goal.
  options.map.relocalize.search_below = 0;
  options.trace.clear();
  const MissionRun blind = runClosedLoop(shortCrossing(), options);
  EXPECT_EQ(blind.metrics.relocalisations, 0u);
  EXPECT_FALSE(blind.metrics.reached_goal);
  EXPECT_GT(blind.metrics.left_path_frames, 0u);
}

TEST(RunnerOptions, DefaultsAreValidAndBadOnesAreNamed) {
  EXPECT_NO_THROW(RunOptions{}.validate());
  RunOptions bad;
  bad.control_dt_s = 0;
  EXPECT_THROW(bad.validate(), InvalidInput);
  bad = RunOptions{};
  bad.map.filter.motion.scale_sigma = -0.01;
  EXPECT_THROW(bad.validate(), InvalidInput);
  bad = RunOptions{};
  bad.map.initial_sigma_m = -1;
  try {
    bad.validate();
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("initial_sigma_m"), std::string::npos);
  }
}

TEST(RunnerMetrics, PercentileAndRoadFrameErrors) {
  EXPECT_EQ(percentile({}, 50), 0);
  EXPECT_EQ(percentile({3, 1, 2}, 50), 2);
  EXPECT_EQ(percentile({1, 2, 3, 4, 5, 6, 7, 8, 9, 10}, 99), 10);
  EXPECT_EQ(percentile({1, 2, 3, 4, 5, 6, 7, 8, 9, 10}, 50), 5);
  // The road runs north; the estimate is 0.1 m east (right) and 0.3 m north (ahead) of the truth.
  const PoseError e = poseError(Pose2(10.1, 20.3, kPi / 2 + 0.01), Pose2(10, 20, kPi / 2), kPi / 2);
  EXPECT_NEAR(e.lateral_m, -0.1, 1e-12);
  EXPECT_NEAR(e.along_m, 0.3, 1e-12);
  EXPECT_NEAR(e.heading_rad, 0.01, 1e-12);
  EXPECT_NEAR(e.distance_m, std::hypot(0.1, 0.3), 1e-12);
}

// The campus_dialogue mission, simulated then replayed and run closed loop (about 2 minutes here).
TEST(RunnerCampusDialogue, ReplayAndClosedLoopReachTheGoalWithinTheTargets) {
  registerBuiltinPipelines();
  const fs::path dir = testing::freshTempDir();
  const MissionFile mission = loadMission(testing::mapPath("missions/campus_dialogue.json"));
  simulate(mission, dir / "log");
  for (const MissionRun& run : {runReplay(mission, dir / "log"), runClosedLoop(mission)}) {
    const MissionMetrics& m = run.metrics;
    SCOPED_TRACE(run.mode);
    EXPECT_TRUE(m.reached_goal) << run.outcome;
    EXPECT_LE(m.estimate.lateral_rms_m, 0.05);
    EXPECT_LE(m.estimate.heading_rms_deg, 0.5);
    EXPECT_LE(m.along_after_intersection_max_m, 0.15);
    // Over the whole run (the campus's landmarks and the ground's step).
    EXPECT_LE(m.estimate.along_max_m, 0.10);
    EXPECT_LE(m.estimate.along_rms_m, 0.04);
    EXPECT_EQ(m.intersections_checked, 4u);
    EXPECT_GT(m.odometry_only.max_error_m, 1.0);  // odometry alone drifts past 1 m
    EXPECT_EQ(m.replans, 0u);
    // The encoders read 1 % long: the filter's scale estimate has moved toward 1 / 1.01.
    EXPECT_LT(run.odometry_scale, 0.998);
    EXPECT_GT(run.odometry_scale, 0.985);
  }
}

/// A short mission replayed over its own simulated log reaches its goal through `intersections`
/// intersections, and within 2 m after each the along-road error is inside 15 cm, the
/// lateral and heading errors inside 5 cm and 0.5 deg, while odometry alone drifts past `drift_m`.
void expectTheIntersectionsFixTheAlongRoadError(const char* fixture, std::size_t intersections, double drift_m) {
  registerBuiltinPipelines();
  const fs::path dir = testing::freshTempDir();
  const MissionFile mission = loadMission(testing::fixturePath(fixture));
  simulate(mission, dir / "log");
  const MissionRun run = runReplay(mission, dir / "log");
  const MissionMetrics& m = run.metrics;
  EXPECT_TRUE(m.reached_goal) << run.outcome;
  EXPECT_EQ(m.intersections_checked, intersections);
  EXPECT_GT(m.odometry_only.max_error_m, drift_m);
  EXPECT_LE(m.along_after_intersection_max_m, 0.15);
  EXPECT_LE(m.estimate.lateral_rms_m, 0.05);
  EXPECT_LE(m.estimate.heading_rms_deg, 0.5);
}

// campus_tour's I15 on its own: west along the concrete R23, straight through the T past the brick
// R22. The along-road error the encoders' 2 % pile up on the way (0.6 m) is taken out when R22's
// edges, across the road, come into view.
TEST(RunnerBrickTee, TheBrickBranchFixesTheAlongRoadErrorOnTheConcreteRoad) {
  expectTheIntersectionsFixTheAlongRoadError("missions/brick_tee.json", 1, 0.5);
}

// campus_tour's first 100 m: straight through the Ts I8 and I9, whose branches leave to the left
// and are seen only 9-12 m ahead at the top of the frame (7 cm a pixel along the road), where 2 px
// of the road / grass boundary are 0.14 m along the road (docs/measurements.md).
TEST(RunnerTourTees, TheBranchesFixTheAlongRoadErrorAtBothTees) {
  expectTheIntersectionsFixTheAlongRoadError("missions/tour_tees.json", 2, 1.0);
}

}  // namespace
}  // namespace mapnav
