// The HTML report end to end: `mapnav replay --report` over a log with a black frame, opened in
// headless Chromium (a screenshot that is not blank, the DOM with every part), and `mapnav demo`.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "mapnav/core/io.h"
#include "mapnav/image/png.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;
using testing::runCli;

constexpr const char* kChromium = "/usr/bin/chromium";

// Chromium headless on `page` with a fresh profile and nothing that phones home; `mode` is
// "--screenshot=FILE" or "--dump-dom". Killed after two minutes.
testing::CommandResult chromium(const fs::path& page, const std::string& mode, const fs::path& profile) {
  return testing::runProgram("/usr/bin/timeout",
                             {"120", kChromium, "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                              "--no-first-run", "--disable-background-networking", "--disable-component-update",
                              "--disable-sync", "--user-data-dir=" + profile.string(), mode, "--window-size=1280,2000",
                              "file://" + fs::absolute(page).string()});
}

// The short crossing simulated, frame 20 black: Vision fails there and the mission resumes.
fs::path logWithABlackFrame(const fs::path& dir, const std::string& mission) {
  const auto sim = runCli({"simulate", "--mission", mission, "-o", (dir / "log").string()});
  EXPECT_EQ(sim.exit_code, 0) << sim.err;
  const fs::path image = dir / "log" / "images" / "000020.png";
  const Image original = readPng(image);
  writePng(Image(original.width, original.height, 3), image);
  return dir / "log";
}

TEST(Report, ReplayWritesAReportThatChromiumShowsWithEveryPart) {
  if (!fs::exists(kChromium)) {
    FAIL() << kChromium << " is missing: run scripts/setup (it installs Debian's chromium, a test tool)";
  }
  const fs::path dir = testing::freshTempDir();
  const std::string mission = testing::fixturePath("missions/short_crossing.json").string();
  const fs::path log = logWithABlackFrame(dir, mission);
  const fs::path report = dir / "report";
  const auto r = runCli({"replay", "--mission", mission, "--log", log.string(), "--report", report.string()});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("vision failures 1, halts 1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("wrote " + (report / "trace.jsonl").string()), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("wrote " + (report / "trajectories.geojson").string()), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("report: " + (report / "report.html").string()), std::string::npos) << r.out;
  ASSERT_TRUE(fs::is_regular_file(report / "report.html"));
  // The GeoJSON: four LineStrings, one position per frame for the trajectories.
  const auto geo = nlohmann::json::parse(readFile(report / "trajectories.geojson"));
  ASSERT_EQ(geo["features"].size(), 4u);
  const std::size_t frames = geo["features"][1]["geometry"]["coordinates"].size();
  EXPECT_GT(frames, 40u);
  EXPECT_EQ(geo["features"][2]["geometry"]["coordinates"].size(), frames);

  // The screenshot: not blank. A page of one colour has no spread; the report has a map, plots and
  // frames: many distinct grey levels and a wide spread.
  const fs::path shot = dir / "shot.png";
  const auto s = chromium(report / "report.html", "--screenshot=" + shot.string(), dir / "profile-1");
  ASSERT_TRUE(fs::is_regular_file(shot)) << "chromium wrote no screenshot (exit " << s.exit_code << "): " << s.err;
  const Image png = readPng(shot);
  EXPECT_EQ(png.width, 1280);
  EXPECT_EQ(png.height, 2000);
  std::vector<std::size_t> histogram(256, 0);
  double sum = 0, sum2 = 0;
  const std::size_t n = static_cast<std::size_t>(png.width) * png.height;
  std::size_t colourful = 0;  // pixels far from grey: route, trajectories, frames, failures
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint8_t* p = png.data.data() + i * png.channels;
    const int grey = (p[0] + p[1] + p[2]) / 3;
    ++histogram[static_cast<std::size_t>(grey)];
    sum += grey;
    sum2 += static_cast<double>(grey) * grey;
    if (png.channels == 3 && std::max({p[0], p[1], p[2]}) - std::min({p[0], p[1], p[2]}) > 60) ++colourful;
  }
  const double mean = sum / static_cast<double>(n);
  const double sd = std::sqrt(std::max(0.0, sum2 / static_cast<double>(n) - mean * mean));
  const auto levels = std::count_if(histogram.begin(), histogram.end(), [&](std::size_t h) { return h > n / 10000; });
  const std::size_t top = *std::max_element(histogram.begin(), histogram.end());
  std::printf("screenshot %s: mean %.1f, sd %.1f, %ld grey levels, most common level %.0f %%, %.1f %% colourful\n",
              shot.c_str(), mean, sd, static_cast<long>(levels), 100.0 * static_cast<double>(top) / static_cast<double>(n),
              100.0 * static_cast<double>(colourful) / static_cast<double>(n));
  EXPECT_GT(sd, 20.0);
  EXPECT_GT(levels, 64);
  EXPECT_LT(top, n * 9 / 10);  // not a blank page with a few lines on it
  EXPECT_GT(colourful, n / 200);

  // The DOM as Chromium parsed it: every part there.
  const auto dom = chromium(report / "report.html", "--dump-dom", dir / "profile-2");
  ASSERT_EQ(dom.exit_code, 0) << dom.err;
  const std::string& html = dom.out;
  for (const char* part : {"<svg id=\"map-svg\"", "id=\"plot-position\"", "id=\"plot-heading\"", "id=\"plot-distance\"",
                           "id=\"metrics-table\"", "id=\"failure-list\"", "id=\"dialogue-text\""}) {
    EXPECT_NE(html.find(part), std::string::npos) << part;
  }
  // Trajectories on the map: the route, truth, estimate and odometry polylines after the map's own.
  const std::size_t map_start = html.find("<svg id=\"map-svg\""), map_end = html.find("</svg>", map_start);
  EXPECT_GE(testing::occurrences(html.substr(map_start, map_end - map_start), "<polyline"), 4u);
  for (const char* key : {"planned route", "true", "estimate (Map module)", "odometry only"}) {
    EXPECT_NE(html.find(std::string("</svg>") + key + "</span>"), std::string::npos) << key;
  }
  // The strip: between half the bound and the bound, with the black frame marked as a failure.
  const std::size_t thumbs = testing::occurrences(html, "<figure class=\"thumb");
  EXPECT_GE(thumbs, 9u);
  EXPECT_LE(thumbs, 24u);
  EXPECT_EQ(testing::occurrences(html, "data:image/png;base64,iVBORw0KGgo"), thumbs);
  EXPECT_NE(html.find("<figure class=\"thumb failed\" id=\"frame-20\">"), std::string::npos);
  EXPECT_NE(html.find("<li>frame 20 (t 10.0 s): "), std::string::npos);
  EXPECT_GT(testing::occurrences(html, "class=\"matched\""), thumbs);  // the frames' lines matched to the map
  // The dialogue, as `mapnav trace show` says it.
  EXPECT_NE(html.find("User: Robot is at road R2, 30 meters from I1."), std::string::npos);
  EXPECT_NE(html.find("Navigator: Drive on R2 10.0 meters and go straight through I2."), std::string::npos);
}

TEST(Report, RunWritesTheReportToo) {
  const fs::path dir = testing::freshTempDir();
  const std::string mission = testing::fixturePath("missions/short_crossing.json").string();
  const fs::path trace = dir / "elsewhere.jsonl";
  const auto r = runCli({"run", "--mission", mission, "--max-frames", "6", "--report", (dir / "r").string(), "--trace",
                         trace.string(), "--json"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(nlohmann::json::parse(r.out)["frames"], 6);  // --json prints the JSON alone
  EXPECT_TRUE(fs::is_regular_file(trace));
  EXPECT_FALSE(fs::exists(dir / "r" / "trace.jsonl"));  // the report reads the trace given
  const std::string html = readFile(dir / "r" / "report.html");
  EXPECT_NE(html.find("mapnav closed-loop: short crossing"), std::string::npos);
  EXPECT_EQ(testing::occurrences(html, "<figure class=\"thumb"), 6u);
  EXPECT_TRUE(fs::is_regular_file(dir / "r" / "trajectories.geojson"));
}

TEST(Demo, WritesLogTraceAndReportAndRunsAgainOverItsOwnLog) {
  const fs::path dir = testing::freshTempDir() / "demo";
  for (int round = 0; round < 2; ++round) {
    const auto r = runCli({"demo", "-o", dir.string(), "--max-frames", "5"});
    EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
    EXPECT_NE(r.out.find("simulating \"campus dialogue\""), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("  5 frames, "), std::string::npos) << r.out;
    // The log is the first 5 frames: it ends there, and that is what was asked for (exit 0).
    EXPECT_NE(r.out.find("campus dialogue (replay, pipeline sidewalk): the log ended"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("report: " + (dir / "report.html").string()), std::string::npos) << r.out;
  }
  for (const char* file : {"log/log.json", "log/frames.jsonl", "trace.jsonl", "report.html", "trajectories.geojson"}) {
    EXPECT_TRUE(fs::is_regular_file(dir / file)) << file;
  }
  const auto show = runCli({"trace", "show", (dir / "trace.jsonl").string()});
  EXPECT_EQ(show.out.rfind("User: Robot is at road R1, 3 meters from I1.", 0), 0u) << show.out.substr(0, 200);
  // Not a log of an earlier demo: left alone, and the demo says why.
  const fs::path other = testing::freshTempDir() / "other";
  fs::create_directories(other / "log");
  writeFileAtomic(other / "log" / "notes.txt", "mine\n");
  const auto refused = runCli({"demo", "-o", other.string(), "--max-frames", "2"});
  EXPECT_EQ(refused.exit_code, 2);
  EXPECT_NE(refused.err.find("is not a replay log of an earlier demo"), std::string::npos) << refused.err;
  EXPECT_TRUE(fs::is_regular_file(other / "log" / "notes.txt"));
  const auto help = runCli({"demo", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.out.find("report.html"), std::string::npos);
}

}  // namespace
}  // namespace mapnav
