// `mapnav suite random-campus` (the suite of unseen maps, mission_sim/suite.h) end to end on two
// seeds cut to a few frames: the table and the JSON's structure, the same bytes with one thread and
// with two, the figures the same as `mapnav run` gives on the seed's mission file (an independent
// path through the ordinary runner), and bad seed lists named with exit 2.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;
using testing::runCli;

constexpr const char* kFrames = "6";

// `mapnav ARGS --json`'s figures but the wall-clock ones (not the same bytes twice).
nlohmann::json runFigures(const std::vector<std::string>& args) {
  const auto run = runCli(args);
  EXPECT_EQ(run.exit_code, 0) << run.err;
  auto m = nlohmann::json::parse(run.out);
  for (const char* key : {"latency_ms_median", "latency_ms_p99", "latency_ms_max", "vision_ms_median"}) m.erase(key);
  return m;
}

TEST(CliSuite, TwoSeedsAgreeWithMapnavRunOnTheirMissionFilesAndDoNotDependOnThreads) {
  const fs::path dir = testing::freshTempDir();
  const auto suite = runCli({"suite", "random-campus", "--seeds", "3,1", "--max-frames", kFrames, "--json",
                             "--no-wall-time", "-o", dir.string()});
  ASSERT_EQ(suite.exit_code, 0) << suite.err;
  const auto j = nlohmann::json::parse(suite.out);
  EXPECT_EQ(j["suite"], "random-campus");
  EXPECT_EQ(j["junctions"], 3);
  EXPECT_EQ(j["max_frames"], 6);
  EXPECT_EQ(j["goal_tolerance_m"], 0.3);
  EXPECT_EQ(j["map_options"]["park_reset_after_rejections"], 0);  // MapModuleOptions' defaults
  EXPECT_EQ(j["map_options"]["initial_sigma_m"], 0.1);
  ASSERT_EQ(j["runs"].size(), 2u);
  EXPECT_EQ(j["runs"][0]["seed"], 3);  // in the order given
  EXPECT_EQ(j["runs"][1]["seed"], 1);
  const auto& s = j["summary"];
  EXPECT_EQ(s["runs"], 2);
  EXPECT_EQ(s["reached"], 0);  // cut after 6 frames
  EXPECT_EQ(s["frames"], 12);
  EXPECT_EQ(s["errors"], 0);
  EXPECT_EQ(s["targets"]["lateral_rms_median_m"], 0.05);
  EXPECT_FALSE(s.contains("wall_s"));
  // The rows went to stderr as progress: the header, then a row per seed in the order given.
  std::istringstream rows(suite.err);
  std::string header, row3, row1;
  std::getline(rows, header);
  std::getline(rows, row3);
  std::getline(rows, row1);
  EXPECT_NE(header.find("seed"), std::string::npos) << suite.err;
  EXPECT_NE(header.find("2s_alg"), std::string::npos) << suite.err;
  EXPECT_EQ(row3.substr(0, 6), "    3 ") << suite.err;
  EXPECT_EQ(row1.substr(0, 6), "    1 ") << suite.err;

  for (const auto& r : j["runs"]) {
    EXPECT_EQ(r["error"], false) << r["outcome"];
    EXPECT_EQ(r["stopped_early"], true);
    EXPECT_EQ(r["reached"], false);
    const auto& figures = r["run"];
    EXPECT_EQ(figures["frames"], 6);
    EXPECT_EQ(figures["mode"], "closed-loop");
    EXPECT_EQ(r["outcome"], figures["outcome"]);
    EXPECT_FALSE(figures.contains("latency_ms_median"));  // wall-clock: not the same bytes twice
    const std::string seed = std::to_string(r["seed"].get<int>());
    const fs::path mission = dir / ("seed-" + seed) / "mission.json";
    ASSERT_TRUE(fs::is_regular_file(mission));
    ASSERT_TRUE(fs::is_regular_file(dir / ("seed-" + seed) / "map.json"));
    // The ordinary runner on the mission file written: every figure the same.
    EXPECT_EQ(figures, runFigures({"run", "--mission", mission.string(), "--max-frames", kFrames, "--json"}))
        << "seed " << seed;
    EXPECT_EQ(figures["pipeline"], seed == "3" ? "sidewalk" : "color-rgb");  // brick / asphalt
    EXPECT_GT(figures["within_2sigma_lateral"].get<double>(), 0.0) << seed;
    EXPECT_GT(figures["nees_mean"].get<double>(), 0.0) << seed;
  }

  // Two seeds at once: the same bytes.
  const auto both = runCli({"suite", "random-campus", "--seeds", "3,1", "--max-frames", kFrames, "--json",
                            "--no-wall-time", "--threads", "2"});
  ASSERT_EQ(both.exit_code, 0) << both.err;
  EXPECT_EQ(both.out, suite.out);
}

// --map-options reaches every run: the suite's figures are `mapnav run`'s with the same options, and
// a start sigma five times the default's changes the filter's consistency from the first frame.
TEST(CliSuite, MapOptionsReachEveryRun) {
  const fs::path dir = testing::freshTempDir();
  const std::string wide = R"({"initial_sigma_m": 0.5})";
  const auto suite = runCli({"suite", "random-campus", "--seeds", "1", "--max-frames", kFrames, "--json",
                             "--no-wall-time", "-o", dir.string(), "--map-options", wide});
  ASSERT_EQ(suite.exit_code, 0) << suite.err;
  const auto j = nlohmann::json::parse(suite.out);
  EXPECT_EQ(j["map_options"]["initial_sigma_m"], 0.5);
  const auto& figures = j["runs"][0]["run"];
  const std::string mission = (dir / "seed-1" / "mission.json").string();
  EXPECT_EQ(runFigures({"run", "--mission", mission, "--max-frames", kFrames, "--json", "--map-options", wide}), figures);
  EXPECT_NE(runFigures({"run", "--mission", mission, "--max-frames", kFrames, "--json"})["nees_mean"], figures["nees_mean"]);
}

TEST(CliSuite, BadSeedListsAreWrongInputNamingTheOption) {
  for (const char* seeds : {"5-2", "x"}) {
    const auto r = runCli({"suite", "random-campus", "--seeds", seeds});
    EXPECT_EQ(r.exit_code, 1) << seeds;
    EXPECT_EQ(r.out, "") << seeds;
    EXPECT_EQ(r.err.rfind(std::string("mapnav: error: --seeds: '") + seeds + "' is not a seed list", 0), 0u) << r.err;
  }
  const auto junctions = runCli({"suite", "random-campus", "--seeds", "1", "--junctions", "0"});
  EXPECT_EQ(junctions.exit_code, 1);
  EXPECT_NE(junctions.err.find("--junctions"), std::string::npos) << junctions.err;
}

}  // namespace
}  // namespace mapnav
