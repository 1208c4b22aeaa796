// Fault injection in replay: a real simulated log damaged in exactly one way —
// a missing frame, a corrupt PNG, a repeated or backwards timestamp, an odometry spike, a frame of
// another size, a log cut mid-line. By default the replay finishes, skips (or repairs) what it must,
// counts each fault by kind, traces it and lists it in the report; --strict stops at the first with
// an error naming frames.jsonl and the line.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>
#include <numeric>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/image/png.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/map/map_io.h"
#include "mapnav/mission/report.h"
#include "mapnav/mission/runner.h"
#include "mapnav/mission/trace.h"
#include "mapnav/mission_sim/simulate.h"
#include "mapnav/testing/support.h"
#include "mapnav/vision/pipelines.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;

constexpr std::size_t kFrames = 12;

MissionFile shortCrossing() { return loadMission(testing::fixturePath("missions/short_crossing.json")); }

std::vector<std::string> splitLines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    lines.push_back(text.substr(begin, end - begin));
    begin = end + 1;
  }
  return lines;
}

// A simulated log of the first 12 frames of the short crossing, copied fresh for every test to damage.
class DamagedLog : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    registerBuiltinPipelines();
    pristine_ = new fs::path(fs::temp_directory_path() / ("mapnav-faults-test-" + std::to_string(::getpid())));
    fs::remove_all(*pristine_);
    SimulateOptions options;
    options.max_frames = kFrames;
    simulate(shortCrossing(), *pristine_, options);
  }
  static void TearDownTestSuite() {
    fs::remove_all(*pristine_);
    delete pristine_;
  }
  void SetUp() override {
    dir_ = testing::freshTempDir();
    log_ = dir_ / "log";
    fs::copy(*pristine_, log_, fs::copy_options::recursive);
    frames_ = ReplayLog::open(log_).frames();
    ASSERT_EQ(frames_.size(), kFrames);
    lines_ = splitLines(readFile(log_ / "frames.jsonl"));
    ASSERT_EQ(lines_.size(), kFrames);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // frames.jsonl line `n` (1-based) as JSON, and written back.
  nlohmann::json line(int n) const { return nlohmann::json::parse(lines_[n - 1]); }
  void setLine(int n, const nlohmann::json& j) {
    lines_[n - 1] = j.dump();
    writeLines();
  }
  void writeLines(const std::string& tail = "") {
    std::string text;
    for (const std::string& l : lines_) text += l + "\n";
    writeFileAtomic(log_ / "frames.jsonl", text + tail);
  }
  double odometrySum() const {
    return std::accumulate(frames_.begin(), frames_.end(), 0.0,
                           [](double s, const LogFrame& f) { return s + f.odometry.distance_m; });
  }

  MissionRun replay(bool strict = false) {
    RunOptions options;
    options.strict = strict;
    options.trace = dir_ / (strict ? "strict-trace.jsonl" : "trace.jsonl");
    return runReplay(shortCrossing(), log_, options);
  }
  // The strict replay's error: one issue, on `line` of frames.jsonl, with `check`.
  void expectStrictError(int line, const std::string& check) {
    try {
      replay(true);
      FAIL() << "the strict replay went through";
    } catch (const ValidationError& e) {
      EXPECT_EQ(fs::path(e.file()), log_ / "frames.jsonl");
      ASSERT_EQ(e.issues().size(), 1u);
      EXPECT_EQ(e.issues()[0].line, line);
      EXPECT_EQ(e.issues()[0].check, check);
    }
    EXPECT_FALSE(fs::exists(dir_ / "strict-trace.jsonl"));  // a run that throws writes no trace
  }
  // One fault of `kind` on `line`: counted, traced once, read back as a sentence.
  void expectOneFault(const MissionRun& run, LogFaultKind kind, int line) {
    ASSERT_EQ(run.faults.size(), 1u);
    EXPECT_EQ(run.faults[0].kind, kind);
    EXPECT_EQ(run.faults[0].line, line);
    EXPECT_EQ(run.metrics.log_faults[kind], 1u);
    EXPECT_EQ(run.metrics.log_faults.total(), 1u);
    const auto json = nlohmann::json::parse(runToJson(run));
    EXPECT_EQ(json["log_faults"][toString(kind)], 1);
    EXPECT_EQ(json["log_faults"]["total"], 1);
    EXPECT_NE(summaryText(run).find("log faults skipped or repaired: 1 (" + toString(kind) + " 1)"), std::string::npos)
        << summaryText(run);
    const std::string trace = readFile(dir_ / "trace.jsonl");
    EXPECT_EQ(testing::occurrences(trace, "\"type\":\"LogFault\""), 1u);
    EXPECT_NE(trace.find("\"kind\":\"" + toString(kind) + "\",\"line\":" + std::to_string(line)), std::string::npos);
    const std::string dialogue = traceDialogue(trace, "trace.jsonl");
    EXPECT_NE(dialogue.find("Sensors: frames.jsonl line " + std::to_string(line) + ": " + toString(kind)),
              std::string::npos);
  }

  static fs::path* pristine_;
  fs::path dir_, log_;
  std::vector<LogFrame> frames_;
  std::vector<std::string> lines_;
};
fs::path* DamagedLog::pristine_ = nullptr;

TEST_F(DamagedLog, UndamagedHasNoFaults) {
  const MissionRun run = replay();
  EXPECT_TRUE(run.faults.empty());
  EXPECT_EQ(run.metrics.log_faults.total(), 0u);
  EXPECT_EQ(run.frames.size(), kFrames);
  EXPECT_NEAR(run.distance_m, odometrySum(), 1e-9);
  EXPECT_EQ(summaryText(run).find("log faults"), std::string::npos);
  EXPECT_EQ(testing::occurrences(readFile(dir_ / "trace.jsonl"), "LogFault"), 0u);
}

TEST_F(DamagedLog, MissingFrameIsSkippedAndItsOdometryGoesToTheNext) {
  fs::remove(log_ / "images/000003.png");
  const MissionRun run = replay();
  expectOneFault(run, LogFaultKind::MissingImage, 4);
  EXPECT_EQ(run.frames.size(), kFrames - 1);
  EXPECT_DOUBLE_EQ(*run.faults[0].t, frames_[3].t);
  // Nothing driven is lost: the skipped frame's distance is in the next frame's.
  EXPECT_NEAR(run.distance_m, odometrySum(), 1e-9);
  EXPECT_NE(run.faults[0].message.find("images/000003.png"), std::string::npos) << run.faults[0].message;
  expectStrictError(4, "log.missing_image");
}

TEST_F(DamagedLog, CorruptPngIsSkipped) {
  writeFileAtomic(log_ / "images/000005.png", std::string("\x89PNG\r\n\x1a\n but then garbage", 26));
  const MissionRun run = replay();
  expectOneFault(run, LogFaultKind::CorruptImage, 6);
  EXPECT_EQ(run.frames.size(), kFrames - 1);
  EXPECT_EQ(run.faults[0].image, "images/000005.png");
  EXPECT_NEAR(run.distance_m, odometrySum(), 1e-9);
  for (const FrameRecord& f : run.frames) EXPECT_NE(f.index, 5u);
  expectStrictError(6, "log.corrupt_image");
}

TEST_F(DamagedLog, FrameOfAnotherSizeIsSkipped) {
  const Image full = readPng(log_ / "images/000002.png");
  writePng(Image(full.width / 2, full.height / 2, 3), log_ / "images/000002.png");
  const MissionRun run = replay();
  expectOneFault(run, LogFaultKind::ImageSize, 3);
  EXPECT_NE(run.faults[0].message.find(std::to_string(full.width / 2) + "x" + std::to_string(full.height / 2)),
            std::string::npos);
  EXPECT_EQ(run.frames.size(), kFrames - 1);
  expectStrictError(3, "log.image_size");
}

TEST_F(DamagedLog, RepeatedTimestampIsSkippedWithItsOdometry) {
  nlohmann::json l4 = line(4);
  l4["t"] = line(3)["t"];
  setLine(4, l4);
  const MissionRun run = replay();
  expectOneFault(run, LogFaultKind::TimeOrder, 4);
  EXPECT_EQ(run.frames.size(), kFrames - 1);
  EXPECT_NEAR(run.distance_m, odometrySum() - frames_[3].odometry.distance_m, 1e-9);
  expectStrictError(4, "log.time_order");
}

TEST_F(DamagedLog, BackwardsTimestampIsSkipped) {
  nlohmann::json l8 = line(8);
  l8["t"] = frames_[1].t;  // back to frame 1's time
  setLine(8, l8);
  const MissionRun run = replay();
  expectOneFault(run, LogFaultKind::TimeOrder, 8);
  EXPECT_EQ(run.frames.size(), kFrames - 1);
  // The next line is compared with the last frame kept (line 7), so it is fine.
  EXPECT_EQ(run.frames.back().index, kFrames - 2);
  expectStrictError(8, "log.time_order");
}

TEST_F(DamagedLog, OdometrySpikeIsReplacedByThePreviousRate) {
  nlohmann::json l6 = line(6);
  l6["odometry"]["distance_m"] = 50.0;  // 50 m in half a second
  setLine(6, l6);
  const MissionRun run = replay();
  expectOneFault(run, LogFaultKind::OdometrySpike, 6);
  EXPECT_EQ(run.frames.size(), kFrames);  // the frame itself is good
  // Frame 5's distance becomes frame 4's rate over frame 5's interval.
  const double rate = frames_[4].odometry.distance_m / (frames_[4].t - frames_[3].t);
  const double expected = odometrySum() - frames_[5].odometry.distance_m + rate * (frames_[5].t - frames_[4].t);
  EXPECT_NEAR(run.distance_m, expected, 1e-9);
  EXPECT_EQ(run.faults[0].action, "odometry replaced by the previous frame's rate");
  // The pose stays near the truth: the spike did not throw it 50 m ahead.
  EXPECT_LT(run.metrics.estimate.max_error_m, 1.0);
  expectStrictError(6, "log.odometry_spike");
}

// A car's log: 8 m/s is a spike for a sidewalk robot's mission (twice 0.6 m/s, at least 5 m/s) but
// not for one whose speed is 6 m/s (twice that, 12 m/s).
TEST_F(DamagedLog, TheSpikeThresholdIsTwiceTheMissionsSpeedAtLeastFive) {
  nlohmann::json l6 = line(6);
  l6["odometry"]["distance_m"] = 8.0 * (frames_[5].t - frames_[4].t);
  setLine(6, l6);
  expectOneFault(replay(), LogFaultKind::OdometrySpike, 6);
  MissionFile fast = shortCrossing();
  fast.speed_mps = 6;
  const MissionRun run = runReplay(fast, log_, RunOptions{});
  EXPECT_TRUE(run.faults.empty());
  RunOptions fixed;
  fixed.max_odometry_speed_mps = 7;  // given: used as it is
  EXPECT_EQ(runReplay(fast, log_, fixed).faults.size(), 1u);
}

TEST_F(DamagedLog, LogCutMidLineSkipsTheLastLine) {
  const std::string last = lines_.back();
  lines_.pop_back();
  writeLines(last.substr(0, last.size() / 2));  // no newline: the recording stopped mid-line
  const MissionRun run = replay();
  expectOneFault(run, LogFaultKind::Truncated, static_cast<int>(kFrames));
  EXPECT_EQ(run.frames.size(), kFrames - 1);
  EXPECT_NE(run.faults[0].message.find("cut short"), std::string::npos) << run.faults[0].message;
  expectStrictError(static_cast<int>(kFrames), "log.truncated");
}

TEST_F(DamagedLog, EveryFaultAtOnceIsCountedByKindAndListedInTheReport) {
  fs::remove(log_ / "images/000001.png");
  writeFileAtomic(log_ / "images/000003.png", "garbage");
  writePng(Image(8, 8, 3), log_ / "images/000004.png");
  nlohmann::json l6 = line(6), l8 = line(8), l10 = line(10);
  l6["t"] = line(5)["t"];
  l8["odometry"]["dheading_deg"] = 720.0;
  l10["t"] = frames_[0].t;
  lines_[5] = l6.dump();
  lines_[7] = l8.dump();
  lines_[9] = l10.dump();
  const std::string last = lines_.back();
  lines_.pop_back();
  writeLines(last.substr(0, 20));
  const MissionRun run = replay();
  const LogFaultCounts& c = run.metrics.log_faults;
  EXPECT_EQ(c[LogFaultKind::MissingImage], 1u);
  EXPECT_EQ(c[LogFaultKind::CorruptImage], 1u);
  EXPECT_EQ(c[LogFaultKind::ImageSize], 1u);
  EXPECT_EQ(c[LogFaultKind::TimeOrder], 2u);
  EXPECT_EQ(c[LogFaultKind::OdometrySpike], 1u);
  EXPECT_EQ(c[LogFaultKind::Truncated], 1u);
  EXPECT_EQ(c[LogFaultKind::BadLine], 0u);
  EXPECT_EQ(c.total(), 7u);
  ASSERT_EQ(run.faults.size(), 7u);
  const int lines[] = {2, 4, 5, 6, 8, 10, 12};  // file order
  for (std::size_t i = 0; i < 7; ++i) EXPECT_EQ(run.faults[i].line, lines[i]) << i;
  EXPECT_EQ(run.frames.size(), kFrames - 6);
  for (const FrameRecord& f : run.frames) {
    EXPECT_TRUE(std::isfinite(f.estimate.x()) && std::isfinite(f.estimate.y()) && std::isfinite(f.estimate.heading()));
  }
  const std::string trace = readFile(dir_ / "trace.jsonl");
  EXPECT_EQ(testing::occurrences(trace, "\"type\":\"LogFault\""), 7u);
  EXPECT_NE(trace.find("\"log_faults\":7"), std::string::npos);
  EXPECT_NE(traceDialogue(trace, "trace.jsonl").find("7 faults of the log skipped or repaired"), std::string::npos);

  const std::string html = reportHtml(run, loadMap(shortCrossing().map), {}, "");
  EXPECT_NE(html.find("<section id=\"log-faults\">"), std::string::npos);
  EXPECT_EQ(testing::occurrences(html, "<li class=\"time_order\">"), 2u);
  for (const char* kind : {"missing_image", "corrupt_image", "image_size", "odometry_spike", "truncated"}) {
    EXPECT_EQ(testing::occurrences(html, std::string("<li class=\"") + kind + "\">"), 1u) << kind;
  }
  EXPECT_NE(html.find("frames.jsonl line 12"), std::string::npos);
  // Strict: the first fault in file order.
  expectStrictError(2, "log.missing_image");
}

}  // namespace
}  // namespace mapnav
