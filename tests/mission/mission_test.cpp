#include "mapnav/mission_sim/simulate.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <tuple>

#include <nlohmann/json.hpp>

#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/logs/replay_log.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;

MissionFile mission(const std::string& name) { return loadMission(testing::mapPath("missions/" + name)); }

// A mission on the campus whose member `key` is `block` (JSON text), written to `dir` and loaded.
MissionFile missionWith(const fs::path& dir, const std::string& key, const std::string& block) {
  writeFileAtomic(dir / "m.json", R"({"format": "mapnav-mission/1", "map": ")" + testing::mapPath("cmu_campus.json").string() +
                                      R"(", "camera": ")" + testing::mapPath("cameras/terregator_pinhole.json").string() +
                                      R"(", "start": "R1@I1+3", "goal": "R3@I3+2", ")" + key + "\": " + block + "}");
  return loadMission(dir / "m.json");
}

// Each (block, check, pointer): the mission with that `key` block fails with that one issue.
void expectOneIssueEach(const std::string& key,
                        const std::vector<std::tuple<std::string, std::string, std::string>>& cases) {
  const fs::path dir = testing::freshTempDir();
  for (const auto& [block, check, where] : cases) {
    try {
      missionWith(dir, key, block);
      ADD_FAILURE() << block;
    } catch (const ValidationError& e) {
      ASSERT_EQ(e.issues().size(), 1u) << block;
      EXPECT_EQ(e.issues()[0].check, check) << block;
      EXPECT_EQ(e.issues()[0].where, where) << block;
    }
  }
}

TEST(ExampleMissions, CampusDialogueIsThePapersDialogue) {
  const MissionFile m = mission("campus_dialogue.json");
  EXPECT_EQ(toString(m.start), "R1@I1+3");
  EXPECT_EQ(toString(m.goal), "R3@I3+2");
  EXPECT_TRUE(fs::is_regular_file(m.map));
  EXPECT_TRUE(fs::is_regular_file(m.camera));
}

TEST(ExampleMissions, TheTourPassesEightIntersectionsAndTheParkLoopCoversEightHundredMetres) {
  const fs::path dir = testing::freshTempDir();
  SimulateOptions one_frame;
  one_frame.max_frames = 1;
  const SimulateResult tour = simulate(mission("campus_tour.json"), dir / "tour", one_frame);
  EXPECT_GE(std::set<std::string>(tour.intersections.begin(), tour.intersections.end()).size(), 8u);
  const SimulateResult park = simulate(mission("park_loop.json"), dir / "park", one_frame);
  EXPECT_GE(park.route_length_m, 800.0);
  EXPECT_EQ(park.frames, 1u);
}

TEST(Simulate, WritesALogWithTruthOdometryAndMasksThatReadsBack) {
  const fs::path dir = testing::freshTempDir();
  SimulateOptions options;
  options.max_frames = 6;
  const SimulateResult r = simulate(mission("campus_dialogue.json"), dir / "log", options);
  EXPECT_EQ(r.frames, 6u);
  const ReplayLog log = ReplayLog::open(dir / "log", ReadOptions{false, true});
  ASSERT_EQ(log.frames().size(), 6u);
  EXPECT_NEAR(log.frames()[1].t - log.frames()[0].t, 0.5, 1e-9);  // 2 Hz
  double odometry = 0;
  for (const LogFrame& f : log.frames()) {
    ASSERT_TRUE(f.truth);
    ASSERT_TRUE(f.mask);
    odometry += f.odometry.distance_m;
  }
  // 0.6 m/s for 2.5 s from a standstill (0.5 m/s^2): about 1.2 m, with a 1 % scale error.
  const double truth = (log.frames().back().truth->translation() - log.frames().front().truth->translation()).norm();
  EXPECT_NEAR(odometry, truth * 1.01, 0.05);
  EXPECT_GT(truth, 0.8);
  // The first frame's truth is the mission's start: 3 m from I1 along R1.
  EXPECT_VEC2_NEAR(log.frames()[0].truth->translation(), Vec2(53, 40), 0.2);
}

TEST(Simulate, TheSameSeedGivesTheSameBytesAndAnotherSeedOtherTextures) {
  const fs::path dir = testing::freshTempDir();
  SimulateOptions options;
  options.max_frames = 2;
  options.seed = 5;
  simulate(mission("campus_dialogue.json"), dir / "a", options);
  simulate(mission("campus_dialogue.json"), dir / "b", options);
  options.seed = 6;
  simulate(mission("campus_dialogue.json"), dir / "c", options);
  for (const char* file : {"frames.jsonl", "images/000001.png", "masks/000001.png"}) {
    EXPECT_EQ(readFile(dir / "a" / file), readFile(dir / "b" / file)) << file;
  }
  EXPECT_NE(readFile(dir / "a/images/000001.png"), readFile(dir / "c/images/000001.png"));
  EXPECT_EQ(readFile(dir / "a/masks/000001.png"), readFile(dir / "c/masks/000001.png"));  // the road is the road
}

TEST(LoadMission, ReportsEveryProblemWithItsPointer) {
  const fs::path dir = testing::freshTempDir();
  writeFileAtomic(dir / "m.json", std::string_view(R"({"format": "mapnav-mission/1", "map": "nowhere.json",
    "camera": "../x.json", "start": "R1@I1", "goal": "R3@I3+2", "via": ["R1@I1+1", 7], "speed_mps": 0,
    "world": [], "colour": "blue"})"));
  try {
    loadMission(dir / "m.json");
    FAIL();
  } catch (const ValidationError& e) {
    std::vector<std::pair<std::string, std::string>> got;
    for (const Issue& issue : e.issues()) got.emplace_back(issue.check, issue.where);
    const std::vector<std::pair<std::string, std::string>> expected{
        {"mission.missing_file", "/map"},          {"mission.missing_file", "/camera"},
        {"mission.road_position", "/start"},       {"mission.road_position", "/via/1"},
        {"schema.range", "/speed_mps"},            {"schema.type", "/world"},
        {"schema.unknown_field", "/colour"},
    };
    EXPECT_EQ(got, expected);
  }
}

TEST(ParseMission, ResolvesFilesAgainstTheGivenPathAndTakesItsStemAsTheDefaultName) {
  const fs::path path = testing::mapPath("missions/from_text.json");
  Issues issues;
  const auto m = parseMission(R"({"format": "mapnav-mission/1", "map": "../cmu_campus.json",
    "camera": "../cameras/terregator_pinhole.json", "start": "R1@I1+3", "goal": "R3@I3+2"})", path, issues);
  ASSERT_TRUE(m.has_value()) << (issues.empty() ? "" : formatIssue(issues[0], "text"));
  EXPECT_TRUE(issues.empty());
  EXPECT_EQ(m->name, "from_text");
  EXPECT_EQ(m->map, path.parent_path() / "../cmu_campus.json");
  EXPECT_EQ(m->goal, (RoadPosition{"R3", "I3", 2.0, 0.0}));
}

TEST(ParseMission, TextThatIsNotJsonGivesNothingAndASyntaxIssueWithoutThrowing) {
  Issues issues;
  EXPECT_FALSE(parseMission("{\"format\": ", "m.json", issues).has_value());
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].check, "json.syntax");
}

// Found by fuzz_mission: a name longer than the file system allows made is_regular_file throw
// std::filesystem::filesystem_error out of loadMission.
TEST(ParseMission, ANameTheFileSystemRefusesIsAMissingFileNotAnException) {
  Issues issues;
  const std::string text = R"({"format": "mapnav-mission/1", "map": "../cmu_campus.json", "camera": ")" +
                           std::string(300, 'c') + R"(", "start": "R1@I1+3", "goal": "R3@I3+2"})";
  EXPECT_FALSE(parseMission(text, testing::mapPath("missions/long.json"), issues).has_value());
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].check, "mission.missing_file");
  EXPECT_EQ(issues[0].where, "/camera");
  EXPECT_NE(issues[0].message.find("File name too long"), std::string::npos) << issues[0].message;
}

TEST(LoadMission, TheHaltBlockSaysWhenTheOperatorHandsControlBack) {
  EXPECT_EQ(mission("campus_dialogue.json").halt.resume_after_frames, std::optional<std::size_t>(2));  // the default
  const fs::path dir = testing::freshTempDir();
  auto load = [&](const std::string& halt) { return missionWith(dir, "halt", halt); };
  EXPECT_EQ(load(R"({"resume_after_frames": 5})").halt.resume_after_frames, std::optional<std::size_t>(5));
  EXPECT_EQ(load(R"({"resume_after_frames": 0})").halt.resume_after_frames, std::optional<std::size_t>(0));
  EXPECT_FALSE(load(R"({"resume_after_frames": null})").halt.resume_after_frames);
  expectOneIssueEach("halt", {{R"({"resume_after_frames": -1})", "schema.range", "/halt/resume_after_frames"},
                              {R"({"resume_after_frames": 1.5})", "schema.type", "/halt/resume_after_frames"},
                              {R"({"resume_after_frames": "never"})", "schema.type", "/halt/resume_after_frames"},
                              {R"({"resume": 2})", "schema.unknown_field", "/halt/resume"},
                              {R"([])", "schema.type", "/halt"}});
}

TEST(LoadMission, TheLocalizationBlockTurnsTheGnssFixesOn) {
  EXPECT_FALSE(mission("campus_dialogue.json").use_gnss);  // the default
  const fs::path dir = testing::freshTempDir();
  auto load = [&](const std::string& block) { return missionWith(dir, "localization", block); };
  EXPECT_TRUE(load(R"({"use_gnss": true})").use_gnss);
  EXPECT_FALSE(load(R"({"use_gnss": false})").use_gnss);
  EXPECT_FALSE(load(R"({})").use_gnss);
  expectOneIssueEach("localization", {{R"({"use_gnss": 1})", "schema.type", "/localization/use_gnss"},
                                      {R"({"gnss": true})", "schema.unknown_field", "/localization/gnss"},
                                      {R"(true)", "schema.type", "/localization"}});
}

TEST(LoadMission, TheWorldsMapIsAFileBesideTheMissionAndNotARendererOption) {
  EXPECT_TRUE(mission("campus_dialogue.json").world_map.empty());  // the default: the mission's map
  const fs::path dir = testing::freshTempDir();
  writeFileAtomic(dir / "surveyed.json", std::string_view("{}"));
  const MissionFile m = missionWith(dir, "world", R"({"map": "surveyed.json", "seed": 3})");
  EXPECT_EQ(m.world_map, dir / "surveyed.json");
  EXPECT_EQ(nlohmann::json::parse(m.world_json), nlohmann::json::parse(R"({"seed": 3})"));
  expectOneIssueEach("world", {{R"({"map": "nowhere.json"})", "mission.missing_file", "/world/map"},
                               {R"({"map": 3})", "schema.type", "/world/map"}});
}

// The world's map must have the mission map's roads by id between the same intersections: each
// difference is an issue, the error names the world's map file, and no log is begun.
TEST(Simulate, AWorldMapWithoutTheMapsRoadsIsAnErrorNamingItAndEveryDifference) {
  const fs::path dir = testing::freshTempDir();
  MissionFile m = mission("campus_dialogue.json");
  nlohmann::json world = nlohmann::json::parse(readFile(m.map));
  auto& roads = world["roads"];
  roads.erase(std::remove_if(roads.begin(), roads.end(), [](const nlohmann::json& r) { return r["id"] == "R25"; }), roads.end());
  auto& intersections = world["intersections"];
  intersections.erase(std::remove_if(intersections.begin(), intersections.end(),
                                     [](const nlohmann::json& i) { return i["id"] == "I17"; }),
                      intersections.end());
  world["landmarks"] = nlohmann::json::array();
  for (auto& r : roads) {
    if (r["id"] != "R4") continue;
    std::swap(r["from"], r["to"]);
    std::reverse(r["centerline"].begin(), r["centerline"].end());
    std::swap(r["left"], r["right"]);
  }
  m.world_map = dir / "world.json";
  writeFileAtomic(m.world_map, world.dump());
  try {
    simulate(m, dir / "log");
    FAIL() << "simulated in a world without R25";
  } catch (const ValidationError& e) {
    EXPECT_EQ(e.file(), m.world_map.string());
    std::vector<std::string> messages;
    for (const Issue& issue : e.issues()) {
      EXPECT_EQ(issue.check, "world.same_roads");
      messages.push_back(issue.message);
    }
    ASSERT_EQ(messages.size(), 3u);
    EXPECT_NE(messages[0].find("intersection \"I17\""), std::string::npos) << messages[0];
    EXPECT_NE(messages[1].find("road \"R4\" runs I4 -> I2 in the world's map but I2 -> I4"), std::string::npos) << messages[1];
    EXPECT_NE(messages[2].find("road \"R25\""), std::string::npos) << messages[2];
  }
  EXPECT_FALSE(fs::exists(dir / "log"));
}

TEST(Simulate, ABadWorldBlockOrAnExistingLogLeavesNothingBehind) {
  const fs::path dir = testing::freshTempDir();
  MissionFile m = mission("campus_dialogue.json");
  m.world_json = R"({"shadow_k": 3, "sunshine": 1})";
  EXPECT_THROW(simulate(m, dir / "log"), ValidationError);
  EXPECT_FALSE(fs::exists(dir / "log"));
  fs::create_directories(dir / "full");
  writeFileAtomic(dir / "full" / "keep.txt", std::string_view("x"));
  SimulateOptions one;
  one.max_frames = 1;
  EXPECT_THROW(simulate(mission("campus_dialogue.json"), dir / "full", one), IoError);
  EXPECT_EQ(readFile(dir / "full" / "keep.txt"), "x");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1) << "no partial folders left";
}

}  // namespace
}  // namespace mapnav
