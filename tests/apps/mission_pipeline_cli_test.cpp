// Pipeline choice end to end: every shipped mission names its pipeline (park_loop runs the edge tracker as
// shipped), a mission without `vision` over paved roads of both families runs the sidewalk pipeline,
// and one whose route's surfaces do not decide one is an error before the first frame that says to
// name one (docs/mission-format.md, "Which pipeline").
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "mapnav/core/io.h"
#include "mapnav/map/generate.h"
#include "mapnav/map/map_io.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;
using testing::runCli;

TEST(CliMissionPipeline, TheParkLoopAsShippedRunsTheEdgeTracker) {
  const auto run = runCli({"run", "--mission", testing::mapPath("missions/park_loop.json").string(), "--max-frames", "2",
                           "--json"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto r = nlohmann::json::parse(run.out);
  EXPECT_EQ(r["pipeline"], "edge-tracker");
  EXPECT_EQ(r["vision_failures"], 0);
}

// A 2 x 2 grid map in `dir` whose road H0_0 is `first` and every other `rest`, and a mission on it
// from H0_0 (5 m from I0_0) right at I1_0 onto V1_0 (10 m along), without `vision` unless `more`
// adds it: the mission file, dir / `file`.
fs::path mixedSurfaceMission(const fs::path& dir, const std::string& first, const std::string& rest,
                             const std::string& file = "m.json", const std::string& more = "") {
  GridMapOptions o;
  o.columns = o.rows = 2;
  MapData data = makeGridMap(o);
  for (Road& r : data.roads) r.surface = r.id == "H0_0" ? first : rest;
  saveMap(data, dir / "grid.json");
  writeFileAtomic(dir / file, R"({"format": "mapnav-mission/1", "map": "grid.json", "camera": ")" +
                                      testing::mapPath("cameras/terregator_pinhole.json").string() +
                                      R"(", "start": "H0_0@I0_0+5", "goal": "V1_0@I1_0+10")" + more + "}");
  return dir / file;
}

// Asphalt, then brick, at the defaults: the sidewalk pipeline (a road class per surface in view)
// drives both and reaches the goal.
TEST(CliMissionPipeline, AMissionWithoutVisionOnAsphaltThenBrickRunsTheSidewalkPipelineToItsGoal) {
  const fs::path mission = mixedSurfaceMission(testing::freshTempDir(), "asphalt", "brick");
  const auto run = runCli({"run", "--mission", mission.string(), "--json"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto r = nlohmann::json::parse(run.out);
  EXPECT_EQ(r["pipeline"], "sidewalk");
  EXPECT_EQ(r["reached_goal"], true) << r["outcome"];
  EXPECT_EQ(r["vision_failures"], 0);
  EXPECT_EQ(r["left_path_frames"], 0);
}

// Asphalt, then dirt: no pipeline here is known to follow both at its defaults; the error before
// the first frame says so and to name one, and named (in the mission or for the run) it runs.
TEST(CliMissionPipeline, AMissionWithoutVisionOnAsphaltThenDirtSaysToNameOne) {
  const fs::path dir = testing::freshTempDir();
  const fs::path mission = mixedSurfaceMission(dir, "asphalt", "dirt");
  const auto run = runCli({"run", "--mission", mission.string(), "--max-frames", "2"});
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_EQ(run.out, "");
  EXPECT_EQ(run.err,
            "mapnav: error: mission \"m\": names no vision pipeline, and the surfaces of the roads its route drives do "
            "not decide one: asphalt (H0_0) calls for color-rgb; dirt (V1_0) calls for edge-tracker. Name the "
            "pipeline in the mission, \"vision\": {\"pipeline\": \"NAME\"}, or for the run (`mapnav pipelines` "
            "lists them); on the command line: --pipeline NAME\n");
  const fs::path named =
      mixedSurfaceMission(dir, "asphalt", "dirt", "named.json", R"(, "vision": {"pipeline": "edge-tracker"})");
  const auto in_mission = runCli({"run", "--mission", named.string(), "--max-frames", "2", "--json"});
  ASSERT_EQ(in_mission.exit_code, 0) << in_mission.err;
  EXPECT_EQ(nlohmann::json::parse(in_mission.out)["pipeline"], "edge-tracker");
  const auto option =
      runCli({"run", "--mission", mission.string(), "--max-frames", "2", "--json", "--pipeline", "color-rgb"});
  ASSERT_EQ(option.exit_code, 0) << option.err;
  EXPECT_EQ(nlohmann::json::parse(option.out)["pipeline"], "color-rgb");
}

// --displace: fault injection for recovery, its text checked before the first frame.
TEST(CliMissionDisplace, BadTextIsAnErrorNamingTheOptionAndAGoodOneIsRecovered) {
  const std::string mission = testing::fixturePath("missions/short_crossing.json").string();
  const std::string expected =
      "expected FRAME,FORWARD,LEFT: a frame index and metres along and to the left of the estimated heading, e.g. "
      "120,1.5,-0.8";
  for (const auto& [text, why] : std::vector<std::pair<std::string, std::string>>{
           {"6,1.5", ""},
           {"6,1.5,-0.8,2", ""},
           {"x,1.5,-0.8", "\"x\" is not a number; "},
           {"-1,1.5,-0.8", "the frame is not an index; "},
           {"2.5,1.5,-0.8", "the frame is not an index; "},
           {"6,1.5m,-0.8", "\"1.5m\" is not a number; "},
           {"6,1.5,nan", "\"nan\" is not a number; "}}) {
    const auto run = runCli({"run", "--mission", mission, "--max-frames", "2", "--displace", text});
    EXPECT_EQ(run.exit_code, 1) << text;
    EXPECT_EQ(run.out, "") << text;
    EXPECT_EQ(run.err, "mapnav: error: --displace \"" + text + "\": " + why + expected + "\n") << text;
  }
  const auto run = runCli({"run", "--mission", mission, "--displace", "6,1.5,-0.8", "--json", "--map-options",
                           R"({"integrity_departure_probability": 1})"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto r = nlohmann::json::parse(run.out);
  EXPECT_EQ(r["relocalisations"], 1);
  EXPECT_GE(r["lost_frames"].get<int>(), 1);
  EXPECT_EQ(r["left_path_frames"], 0);
}

}  // namespace
}  // namespace mapnav
