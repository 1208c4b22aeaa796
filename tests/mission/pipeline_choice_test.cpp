// Every mission names its pipeline; a mission without `vision` gets the pipeline its map's
// surfaces call for, or an error that says to name one (docs/mission-format.md, "Which pipeline").
#include "mapnav/mission/pipeline_choice.h"

#include <gtest/gtest.h>

#include <tuple>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/map/generate.h"
#include "mapnav/map/map_io.h"
#include "mapnav/mission/mission_file.h"
#include "mapnav/mission/runner.h"
#include "mapnav/mission_sim/closed_loop.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"
#include "mapnav/vision/pipelines.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;

TEST(PipelineForSurface, SlabsCallForTheSidewalkClassifierAsphaltAndGravelForRgbDirtForTheEdgeTracker) {
  for (const auto& [surface, pipeline] : std::vector<std::pair<std::string, std::string>>{
           {"concrete", "sidewalk"}, {"brick", "sidewalk"}, {"asphalt", "color-rgb"}, {"dirt", "edge-tracker"},
           {"gravel", "color-rgb"}, {"grass", ""}, {"tarmac", ""}, {"", ""}}) {
    EXPECT_EQ(pipelineForSurface(surface), pipeline) << surface;
  }
}

TEST(PipelineForRoads, TheExampleMapsDecide) {
  const Map& campus = testing::campusMap();
  std::vector<std::string> all;
  for (const Road& r : campus.roads()) all.push_back(r.id);
  EXPECT_EQ(pipelineForRoads(campus, all, "campus"), "sidewalk");  // 24 concrete roads and a brick one
  const Map park = loadMap(testing::mapPath("park_path.json"));
  EXPECT_EQ(pipelineForRoads(park, {"R1", "R2", "R5"}, "park"), "color-rgb");  // asphalt
}

// A 2 x 2 grid (roads H0_0, H0_1, V0_0, V1_0, 40 m) with the given surfaces.
Map grid(const std::vector<std::pair<std::string, std::string>>& surfaces) {
  GridMapOptions o;
  o.columns = o.rows = 2;
  MapData data = makeGridMap(o);
  for (Road& r : data.roads) {
    for (const auto& [id, surface] : surfaces) {
      if (r.id == id) r.surface = surface;
    }
  }
  return Map(std::move(data));
}

TEST(PipelineForRoads, RoadsThatCallForDifferentPipelinesOrNoneAreAnErrorSayingToNameOne) {
  const Map mixed = grid({{"H0_0", "asphalt"}, {"V1_0", "brick"}, {"H0_1", "brick"}});
  // Paved roads of both families: the pipeline with a road class per surface.
  EXPECT_EQ(pipelineForRoads(mixed, {"H0_0", "V1_0", "H0_1", "H0_0"}, "mission \"m\""), "sidewalk");
  const Map park = grid({{"H0_0", "asphalt"}, {"V1_0", "dirt"}, {"H0_1", "brick"}});
  try {
    pipelineForRoads(park, {"H0_0", "V1_0", "H0_1", "H0_0"}, "mission \"m\"");
    ADD_FAILURE() << "no error";
  } catch (const NoPipelineChosen& e) {
    EXPECT_EQ(std::string(e.what()),
              "mission \"m\": names no vision pipeline, and the surfaces of the roads its route drives do not decide "
              "one: asphalt (H0_0) calls for color-rgb; dirt (V1_0) calls for edge-tracker; brick (H0_1) calls for "
              "sidewalk. Name the pipeline in the mission, \"vision\": {\"pipeline\": \"NAME\"}, or for the run "
              "(`mapnav pipelines` lists them)");
  }
  // Roads the route does not drive do not count; a surface no pipeline follows decides nothing.
  EXPECT_EQ(pipelineForRoads(mixed, {"H0_0"}, "m"), "color-rgb");
  EXPECT_EQ(pipelineForRoads(mixed, {"V1_0", "H0_1"}, "m"), "sidewalk");
  const Map lawn = grid({{"H0_0", "grass"}});
  try {
    pipelineForRoads(lawn, {"H0_0"}, "m");
    ADD_FAILURE() << "no error";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("grass (H0_0) calls for no pipeline known to follow it."), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(pipelineForRoads(lawn, {}, "m"), InvalidInput);
  EXPECT_THROW(pipelineForRoads(lawn, {"R9"}, "m"), NotFound);
}

TEST(LoadMission, VisionNamesItsPipeline) {
  const fs::path dir = testing::freshTempDir();
  const std::string head = R"({"format": "mapnav-mission/1", "map": ")" + testing::mapPath("cmu_campus.json").string() +
                           R"(", "camera": ")" + testing::mapPath("cameras/terregator_pinhole.json").string() +
                           R"(", "start": "R1@I1+3", "goal": "R3@I3+2")";
  auto load = [&](const std::string& rest) {
    writeFileAtomic(dir / "m.json", head + rest + "}");
    return loadMission(dir / "m.json");
  };
  EXPECT_EQ(load("").vision_pipeline, "");
  const MissionFile named = load(R"(, "vision": {"pipeline": "edge-tracker", "options": {"single_edge": true}})");
  EXPECT_EQ(named.vision_pipeline, "edge-tracker");
  EXPECT_EQ(named.vision_options_json, R"({"single_edge":true})");
  for (const auto& [vision, check, where] : std::vector<std::tuple<std::string, std::string, std::string>>{
           {R"({"pipeline": ""})", "schema.range", "/vision/pipeline"},
           {R"({"options": {"max_distance_m": 1.0}})", "schema.required", "/vision"},
           {R"({"pipeline": 3})", "schema.type", "/vision/pipeline"}}) {
    try {
      load(R"(, "vision": )" + vision);
      ADD_FAILURE() << vision;
    } catch (const ValidationError& e) {
      ASSERT_EQ(e.issues().size(), 1u) << vision;
      EXPECT_EQ(e.issues()[0].check, check) << vision;
      EXPECT_EQ(e.issues()[0].where, where) << vision;
    }
  }
}

TEST(ExampleMissions, EveryMissionNamesItsPipeline) {
  for (const auto& [name, pipeline] : std::vector<std::pair<std::string, std::string>>{
           {"campus_dialogue.json", "sidewalk"}, {"campus_tour.json", "sidewalk"}, {"park_loop.json", "edge-tracker"}}) {
    EXPECT_EQ(loadMission(testing::mapPath("missions/" + name)).vision_pipeline, pipeline) << name;
  }
  for (const fs::directory_entry& e : fs::directory_iterator(testing::mapPath("missions"))) {
    EXPECT_FALSE(loadMission(e.path()).vision_pipeline.empty()) << e.path();
  }
}

// A mission without `vision` on a 2 x 2 grid whose route drives H0_0 then V1_0, with those surfaces.
MissionFile gridMission(const fs::path& dir, const std::string& h, const std::string& v) {
  GridMapOptions o;
  o.columns = o.rows = 2;
  MapData data = makeGridMap(o);
  for (Road& r : data.roads) r.surface = r.id == "H0_0" ? h : r.id == "V1_0" ? v : "grass";
  saveMap(data, dir / "grid.json");
  writeFileAtomic(dir / "m.json", R"({"format": "mapnav-mission/1", "map": "grid.json", "camera": ")" +
                                      testing::mapPath("cameras/terregator_pinhole.json").string() +
                                      R"(", "start": "H0_0@I0_0+5", "goal": "V1_0@I1_0+10"})");
  return loadMission(dir / "m.json");
}

TEST(MissionPipeline, WithoutVisionTheRouteSurfacesChooseAndTheCallerOverrides) {
  registerBuiltinPipelines();
  const fs::path dir = testing::freshTempDir();
  RunOptions one;
  one.max_frames = 1;
  EXPECT_EQ(runClosedLoop(gridMission(dir, "asphalt", "gravel"), one).pipeline, "color-rgb");
  EXPECT_EQ(runClosedLoop(gridMission(dir, "concrete", "brick"), one).pipeline, "sidewalk");
  EXPECT_EQ(runClosedLoop(gridMission(dir, "asphalt", "brick"), one).pipeline, "sidewalk");  // both families
  const MissionFile mixed = gridMission(dir, "asphalt", "dirt");
  EXPECT_THROW(runClosedLoop(mixed, one), InvalidInput);
  one.pipeline = "cluster-perceptron";
  EXPECT_EQ(runClosedLoop(mixed, one).pipeline, "cluster-perceptron");
}

}  // namespace
}  // namespace mapnav
