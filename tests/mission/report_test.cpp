// The mission report on a hand-made run: the strip keeps evenly spaced frames and the failures'
// first frames within its bound, the thumbnails are the frames shrunk by box averaging, the HTML is
// self-contained and has every part, and the GeoJSON trajectories read back to the run's poses.
#include "mapnav/mission/report.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/image/png.h"
#include "mapnav/map/geodesy.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;

// Six frames along x at 1 m a frame; the estimate 1 cm left of the truth, odometry drifting 0.1 m
// left per frame; Vision fails on frames 3 and 4 and the halt lasts to frame 5.
MissionRun handMadeRun() {
  MissionRun run;
  run.mode = "replay";
  run.mission = "hand made";
  run.pipeline = "sidewalk";
  run.image_width = 512;
  run.image_height = 480;
  run.route.line = Polyline2({Vec2(0, 0), Vec2(10, 0)});
  run.route.length_m = 10;
  run.start = Pose2(Vec2(0, 0), 0);
  run.goal = Pose2(Vec2(10, 0), 0);
  for (std::size_t i = 0; i < 6; ++i) {
    FrameRecord f;
    f.index = i;
    f.t = 0.5 * static_cast<double>(i);
    f.truth = Pose2(Vec2(static_cast<double>(i), 0), 0);
    f.estimate = Pose2(Vec2(static_cast<double>(i), 0.01), 0);
    f.odometry_only = Pose2(Vec2(static_cast<double>(i), 0.1 * static_cast<double>(i)), 0);
    f.error.lateral_m = 0.01;
    f.error.distance_m = 0.01;
    f.odometry_error.lateral_m = f.odometry_error.distance_m = 0.1 * static_cast<double>(i);
    f.vision_ok = i != 3 && i != 4;
    f.vision_reason = f.vision_ok ? "" : "frame too dark";
    f.halted = i >= 3;
    run.frames.push_back(f);
  }
  run.metrics.frames = 6;
  run.metrics.has_truth = true;
  run.metrics.vision_failures = 2;
  run.metrics.halts = 1;
  run.outcome = "the log ended 5.00 m from the goal";
  return run;
}

Image plainFrame(int width, int height, std::uint8_t value) {
  Image image(width, height, 3);
  std::fill(image.data.begin(), image.data.end(), value);
  return image;
}

TEST(ReportFrames, KeepsEvenlySpacedFramesAndTheFirstFrameOfEachFailureWithinTheBound) {
  ReportOptions options;
  options.max_thumbnails = 10;
  options.max_failure_thumbnails = 2;
  options.thumbnail_width_px = 16;
  ReportFrames frames(options);
  const Image rgb = plainFrame(32, 24, 100);
  const PredictedObject predicted;
  const DetectedObject ok;
  const DetectedObject failed = DetectedObject::failed("frame too dark");
  for (std::size_t i = 0; i < 100; ++i) {
    const bool fails = (i >= 50 && i <= 52) || i == 70 || i == 90;
    frames.add(FrameView{i, 0.5 * static_cast<double>(i), &rgb, &predicted, fails ? &failed : &ok});
  }
  // Regular frames: 8 at most; the stride doubles 1 → 2 → 4 → 8 → 16 as the run grows (by hand:
  // frame 64 is the ninth at stride 8). Failures: the onsets 50 and 70; 90 is one too many.
  const std::vector<ReportThumbnail> kept = frames.thumbnails();
  std::vector<std::size_t> indices;
  for (const ReportThumbnail& t : kept) indices.push_back(t.index);
  EXPECT_EQ(indices, (std::vector<std::size_t>{0, 16, 32, 48, 50, 64, 70, 80, 96}));
  EXPECT_FALSE(kept[4].vision_ok);
  EXPECT_EQ(kept[4].reason, "frame too dark");
  EXPECT_TRUE(kept[3].vision_ok);
  EXPECT_DOUBLE_EQ(kept[6].t, 35.0);
  EXPECT_EQ(kept[0].width, 32);
  EXPECT_EQ(kept[0].height, 24);
}

TEST(ReportFrames, AThumbnailIsTheFrameBoxAveragedWithItsLines) {
  ReportOptions options;
  options.thumbnail_width_px = 16;
  ReportFrames frames(options);
  Image rgb = plainFrame(32, 4, 0);
  // The top-left 2 x 2 block: 0, 10, 20, 31 in red → (61 + 2) / 4 = 15 after rounding.
  rgb.pixel(1, 0)[0] = 10;
  rgb.pixel(0, 1)[0] = 20;
  rgb.pixel(1, 1)[0] = 31;
  PredictedObject predicted;
  InterestSegment s;
  s.id = "R1.left.0";
  s.image = Segment2{Vec2(1, 2), Vec2(30, 3)};
  predicted.segments.push_back(s);
  DetectedObject detected;
  DetectedLine matched;
  matched.label = "R1.left.0";
  matched.image = Segment2{Vec2(1, 2.5), Vec2(30, 3)};
  DetectedLine border;
  border.frame_edge = true;
  detected.lines = {matched, border, DetectedLine{}};
  frames.add(FrameView{0, 0.0, &rgb, &predicted, &detected});
  const std::vector<ReportThumbnail> kept = frames.thumbnails();
  ASSERT_EQ(kept.size(), 1u);
  const ReportThumbnail& t = kept[0];
  ASSERT_EQ(t.predicted.size(), 1u);
  EXPECT_EQ(t.predicted[0].b, Vec2(30, 3));
  ASSERT_EQ(t.detected.size(), 2u);  // the frame edge is left out
  EXPECT_EQ(t.detected[0].label, "R1.left.0");
  EXPECT_EQ(t.detected[1].label, "");

  const fs::path png = testing::freshTempDir() / "thumb.png";
  writeFileAtomic(png, t.png);
  const Image small = readPng(png);
  EXPECT_EQ(small.width, 16);
  EXPECT_EQ(small.height, 2);
  EXPECT_EQ(small.pixel(0, 0)[0], 15);
  EXPECT_EQ(small.pixel(0, 0)[1], 0);
  EXPECT_EQ(small.pixel(1, 0)[0], 0);
}

TEST(ReportOptions, ValidateNamesTheField) {
  ReportOptions o;
  o.max_failure_thumbnails = o.max_thumbnails;
  try {
    o.validate();
    FAIL() << "no throw";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "ReportOptions::max_failure_thumbnails = 24: must be < max_thumbnails");
  }
  ReportOptions w;
  w.thumbnail_width_px = 8;
  EXPECT_THROW(ReportFrames{w}, InvalidInput);
  try {
    w.validate();
    FAIL() << "no throw";
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "ReportOptions::thumbnail_width_px = 8: must be in [16, 2048]");
  }
}

TEST(ReportHtml, IsSelfContainedWithEveryPart) {
  const Map& map = testing::campusMap();
  const MissionRun run = handMadeRun();
  ReportFrames frames;
  const Image rgb = plainFrame(512, 480, 90);
  const PredictedObject predicted;
  const DetectedObject ok;
  frames.add(FrameView{0, 0.0, &rgb, &predicted, &ok});
  const std::string html = reportHtml(run, map, frames.thumbnails(), "Map: Vision will see <straight> road & more.\n");

  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  // Nothing to fetch: no scripts, no linked files, no remote addresses (the SVG namespace is a name).
  for (const char* remote : {"<script", "<link", "src=\"", "url(", "href=\"http", "https://"}) {
    EXPECT_EQ(html.find(remote), std::string::npos) << remote;
  }
  for (const char* part : {"id=\"metrics-table\"", "id=\"map-svg\"", "id=\"plot-position\"", "id=\"plot-heading\"",
                           "id=\"plot-distance\"", "id=\"failure-list\"", "id=\"frame-0\"", "id=\"dialogue-text\""}) {
    EXPECT_NE(html.find(part), std::string::npos) << part;
  }
  // The thumbnail is inline PNG ("iVBORw0KGgo" is the base64 of the PNG signature).
  EXPECT_NE(html.find("href=\"data:image/png;base64,iVBORw0KGgo"), std::string::npos);
  // The failures, grouped; the dialogue escaped.
  EXPECT_NE(html.find("<li>frames 3&ndash;4 (t 1.5&ndash;2.0 s): frame too dark</li>"), std::string::npos);
  EXPECT_NE(html.find("Map: Vision will see &lt;straight&gt; road &amp; more."), std::string::npos);
  EXPECT_NE(html.find("<th>lateral RMS</th>"), std::string::npos);
  EXPECT_EQ(html.find("<?xml"), std::string::npos);  // the SVGs are inline elements
}

TEST(ReportHtml, TheSummaryHasThePathAgreement) {
  const Map& map = testing::campusMap();
  MissionRun run = handMadeRun();
  PathAgreementSummary s;
  s.frames = 6;
  s.measured = 4;
  s.path_too_short = 2;
  s.inside_goal_frames = 3;
  s.median_inside = 0.9;
  s.median_ground_share = 0.25;
  run.metrics.path_agreement = s;
  const std::string html = reportHtml(run, map, {}, "");
  EXPECT_NE(html.find("<tr><th>path agreement</th><td>road found holds &gt;= 95 % of the true future path in 3 of 4 "
                      "measured frames (median 0.900)</td><td>covers a median 0.250 of the ground in view; no centre "
                      "line</td></tr>"),
            std::string::npos);
  run.metrics.path_agreement.reset();
  run.metrics.has_truth = false;
  EXPECT_NE(reportHtml(run, map, {}, "").find("<tr><th>path agreement</th><td>not measured</td><td>no ground truth</td></tr>"),
            std::string::npos);
}

TEST(ReportHtml, TheSummaryHasTheFilterConsistency) {
  const Map& map = testing::campusMap();
  MissionRun run = handMadeRun();
  run.metrics.has_truth = true;
  run.metrics.consistency.frames = 8;
  run.metrics.consistency.within_2sigma_along = 0.875;
  run.metrics.consistency.within_2sigma_lateral = 1.0;
  run.metrics.consistency.within_2sigma_heading = 0.5;
  run.metrics.consistency.nees_frames = 8;
  run.metrics.consistency.nees_mean = 4.25;
  EXPECT_NE(reportHtml(run, map, {}, "")
                .find("<tr><th>true error within 2 sigma</th><td>along 87.5 %, lateral 100.0 %, heading 50.0 %; mean "
                      "NEES 4.25 (a consistent filter: 95.4 %, NEES 3)</td><td></td></tr>"),
            std::string::npos);
  run.metrics.consistency = FilterConsistency{};  // no frame with truth: no row
  EXPECT_EQ(reportHtml(run, map, {}, "").find("true error within 2 sigma"), std::string::npos);
}

TEST(ReportHtml, SaysWhatFixedTheAlongRoadPositionInTheSummaryAndUnderTheErrorPlot) {
  const Map& map = testing::campusMap();
  MissionRun run = handMadeRun();
  run.metrics.has_truth = true;
  run.frames[1].along_cue = AlongCue::Intersection;
  run.frames[3].along_cue = AlongCue::Landmark;
  run.frames[4].along_cue = AlongCue::Landmark;
  run.metrics.ground_steps_used = 5;
  const std::string html = reportHtml(run, map, {}, "");
  EXPECT_NE(html.find("<tr><th>along-road position fixed by</th><td>1 frames by intersections, 2 by landmarks, 3 by "
                      "neither (odometry)</td><td></td></tr>"),
            std::string::npos);
  EXPECT_NE(html.find("the distance driven measured from the ground on 5 of " + std::to_string(run.metrics.frames) +
                      " frames</td></tr>"),
            std::string::npos);
  // The ticks: two of the landmark colour (#c87800), one of the intersections' (#5a5a5a), in the position plot.
  const std::size_t a = html.find("id=\"plot-position\""), b = html.find("id=\"plot-heading\"");
  ASSERT_NE(a, std::string::npos);
  ASSERT_NE(b, std::string::npos);
  const std::string plot = html.substr(a, b - a);
  EXPECT_EQ(testing::occurrences(plot, "stroke=\"#c87800\""), 2u);
  EXPECT_EQ(testing::occurrences(plot, "stroke=\"#5a5a5a\""), 1u);
}

TEST(ReportGeoJson, TheTrajectoriesReadBackToThePosesThroughTheMapsOrigin) {
  const Map& map = testing::campusMap();
  const MissionRun run = handMadeRun();
  const auto doc = nlohmann::json::parse(trajectoriesGeoJson(run, map));
  EXPECT_EQ(doc["type"], "FeatureCollection");
  ASSERT_EQ(doc["features"].size(), 4u);
  std::vector<std::string> names;
  for (const auto& f : doc["features"]) {
    EXPECT_EQ(f["geometry"]["type"], "LineString");
    names.push_back(f["properties"]["name"]);
  }
  EXPECT_EQ(names, (std::vector<std::string>{"route", "true", "estimate", "odometry"}));
  EXPECT_EQ(doc["features"][0]["geometry"]["coordinates"].size(), 2u);
  // The truth starts at the local origin: the map's origin, lon first (maps/cmu_campus.json).
  const auto& truth = doc["features"][1]["geometry"]["coordinates"];
  ASSERT_EQ(truth.size(), 6u);
  EXPECT_DOUBLE_EQ(truth[0][0].get<double>(), -79.9436);
  EXPECT_DOUBLE_EQ(truth[0][1].get<double>(), 40.4433);
  // Every position back through the origin: within 1 mm of the pose (9 decimals are 0.1 mm).
  const LocalFrame frame(*map.data().origin);
  const auto& odometry = doc["features"][3]["geometry"]["coordinates"];
  for (std::size_t i = 0; i < 6; ++i) {
    const Vec2 t = frame.toLocal(LatLon{truth[i][1].get<double>(), truth[i][0].get<double>()});
    EXPECT_NEAR((t - run.frames[i].truth->translation()).norm(), 0.0, 1e-3) << i;
    const Vec2 o = frame.toLocal(LatLon{odometry[i][1].get<double>(), odometry[i][0].get<double>()});
    EXPECT_NEAR((o - run.frames[i].odometry_only.translation()).norm(), 0.0, 1e-3) << i;
  }
}

// GNSS fixes (a real log's, every other frame here, 0.5 m off the truth to the left, sigma 0.2 m):
// a ring each on the map with their key, and a MultiPoint in the GeoJSON; a run without has neither.
TEST(ReportGnss, FixesAreDrawnOnTheMapAndWrittenToTheGeoJson) {
  const Map& map = testing::campusMap();
  MissionRun run = handMadeRun();
  EXPECT_EQ(reportHtml(run, map, {}, "").find("GNSS fix"), std::string::npos);
  EXPECT_EQ(nlohmann::json::parse(trajectoriesGeoJson(run, map))["features"].size(), 4u);
  for (std::size_t i = 0; i < run.frames.size(); i += 2) {
    run.frames[i].gnss = run.frames[i].truth->translation() + Vec2(0, 0.5);
    run.frames[i].gnss_sigma_m = 0.2;
  }
  const std::string html = reportHtml(run, map, {}, "");
  EXPECT_NE(html.find("GNSS fix (ring: its 1&sigma;)"), std::string::npos);
  const auto doc = nlohmann::json::parse(trajectoriesGeoJson(run, map));
  ASSERT_EQ(doc["features"].size(), 5u);
  const auto& gnss = doc["features"][4];
  EXPECT_EQ(gnss["properties"]["name"], "gnss");
  EXPECT_EQ(gnss["geometry"]["type"], "MultiPoint");
  const auto& points = gnss["geometry"]["coordinates"];
  ASSERT_EQ(points.size(), 3u);
  const LocalFrame frame(*map.data().origin);
  for (std::size_t k = 0; k < 3; ++k) {
    const Vec2 p = frame.toLocal(LatLon{points[k][1].get<double>(), points[k][0].get<double>()});
    EXPECT_NEAR((p - Vec2(2.0 * static_cast<double>(k), 0.5)).norm(), 0.0, 1e-3) << k;
  }
}

TEST(ReportFiles, WritesTheReportAndTheGeoJsonAndNamesABadTrace) {
  const Map& map = testing::campusMap();
  const fs::path dir = testing::freshTempDir() / "report";
  const ReportFiles files = writeReport(dir, handMadeRun(), map, ReportFrames{}, "", "");
  EXPECT_EQ(files.html, dir / "report.html");
  ASSERT_TRUE(files.geojson);
  EXPECT_TRUE(fs::is_regular_file(*files.geojson));
  EXPECT_NE(readFile(files.html).find("No trace was written."), std::string::npos);
  // A trace that does not read back: the error names it, and no report replaces the old one.
  const fs::path other = testing::freshTempDir() / "other";
  EXPECT_THROW(writeReport(other, handMadeRun(), map, ReportFrames{}, "not json\n", "bad.jsonl"), ValidationError);
  EXPECT_FALSE(fs::exists(other / "report.html"));
}

}  // namespace
}  // namespace mapnav
