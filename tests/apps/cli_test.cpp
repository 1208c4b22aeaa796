// The `mapnav` command run end to end: exit codes, messages, files written or not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <random>
#include <set>

#include <nlohmann/json.hpp>

#include "mapnav/core/io.h"
#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/map/map_io.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;
using testing::runCli;

std::string str(const fs::path& p) { return p.string(); }

TEST(Cli, VersionAndHelp) {
  const auto version = runCli({"--version"});
  EXPECT_EQ(version.exit_code, 0);
  EXPECT_EQ(version.out, "mapnav 0.1.0\n");
  for (const std::vector<std::string>& args :
       std::vector<std::vector<std::string>>{{"--help"}, {"map", "--help"}, {"map", "validate", "--help"},
                                             {"map", "info", "--help"}, {"map", "render", "--help"},
                                             {"map", "import-geojson", "--help"}, {"map", "export-geojson", "--help"}}) {
    const auto r = runCli(args);
    EXPECT_EQ(r.exit_code, 0) << args.size();
    EXPECT_NE(r.out.find("Usage"), std::string::npos) << r.out;
  }
  EXPECT_NE(runCli({"map", "render", "--help"}).out.find("OUT.png or OUT.svg"), std::string::npos);
}

TEST(Cli, ValidateExampleMapsExitsZero) {
  const auto r = runCli({"map", "validate", str(testing::mapPath("cmu_campus.json")), str(testing::mapPath("park_path.json")),
                         str(testing::mapPath("cmu_campus.geojson"))});
  EXPECT_EQ(r.exit_code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("cmu_campus.json: valid (0 errors, 0 warnings)"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cmu_campus.geojson: valid (0 errors, 0 warnings)"), std::string::npos) << r.out;
}

TEST(Cli, ValidatePrintsFilePointerSeverityCheckMessage) {
  const std::string file = str(testing::fixturePath("maps/invalid/roads.unknown_intersection.json"));
  const auto r = runCli({"map", "validate", file});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find(file + ":/roads/1/to: error: roads.unknown_intersection: road \"R2\" to \"I4\": no intersection has this id\n"),
            std::string::npos)
      << r.out;
  // Warnings alone do not make a map invalid; the worst file decides the exit code.
  const std::string warned = str(testing::fixturePath("maps/invalid/roads.very_short.json"));
  EXPECT_EQ(runCli({"map", "validate", warned}).exit_code, 0);
  EXPECT_EQ(runCli({"map", "validate", warned, file}).exit_code, 1);
}

TEST(Cli, ValidateGeoJsonPointsIntoTheGeoJsonFile) {
  const fs::path dir = testing::freshTempDir();
  std::string text = readFile(testing::mapPath("cmu_campus.geojson"));
  const std::string width = "\"width\": 2.0";
  const auto at = text.find(width);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, width.size(), "\"width\": -2.0");
  writeFileAtomic(dir / "bad.geojson", text);
  const auto r = runCli({"map", "validate", str(dir / "bad.geojson")});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.out.find("/properties/width: error: roads.invalid_width"), std::string::npos) << r.out;
}

// At least 20 malformed inputs: each is refused with a message naming the file, never a crash.
TEST(Cli, MalformedInputsExitOneOrTwoWithAMessageAndNeverCrash) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(testing::fixturePath("malformed"))) files.push_back(entry.path());
  const fs::path dir = testing::freshTempDir();
  {  // the big ones are made here rather than kept in the repository
    std::ofstream(dir / "deeply_nested.json") << std::string(100000, '[') << std::string(100000, ']');
    std::ofstream huge(dir / "huge_array.json");
    huge << R"({"format": "mapnav-map/1", "name": "m", "surfaces": {}, "intersections": [], "roads": [{"id": "R1", "from": "a",)"
         << R"( "to": "b", "width": 1, "surface": "s", "left": "s", "right": "s", "centerline": [)";
    for (int i = 0; i < 500000; ++i) huge << (i ? ",[0,1e400]" : "[0,1]");
    huge << "]}]}";
    files.push_back(dir / "deeply_nested.json");
    files.push_back(dir / "huge_array.json");
  }
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 25u);
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.filename().string());
    for (const std::string command : {"validate", "info"}) {
      const auto r = runCli({"map", command, str(file)});
      EXPECT_FALSE(r.signaled) << "crashed";
      EXPECT_TRUE(r.exit_code == 1 || r.exit_code == 2) << command << " exit " << r.exit_code;
      EXPECT_NE((r.out + r.err).find(str(file)), std::string::npos) << command << ": " << r.out << r.err;
      EXPECT_LT(r.out.size() + r.err.size(), 20000u) << "a bad file gets a few lines, not a flood";
    }
    const fs::path png = dir / (file.filename().string() + ".png");
    const auto r = runCli({"map", "render", str(file), "-o", str(png)});
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_FALSE(fs::exists(png)) << "no output for a bad map";
  }
}

TEST(Cli, InfoPrintsCountsAndJson) {
  const auto text = runCli({"map", "info", str(testing::mapPath("cmu_campus.json"))});
  EXPECT_EQ(text.exit_code, 0);
  EXPECT_NE(text.out.find("components:    1 (connected)"), std::string::npos) << text.out;
  const auto json = runCli({"map", "info", "--json", str(testing::mapPath("cmu_campus.json"))});
  EXPECT_EQ(json.exit_code, 0);
  const Map& map = testing::campusMap();
  EXPECT_NE(json.out.find("\"roads\": " + std::to_string(map.roads().size())), std::string::npos) << json.out;
  EXPECT_NE(json.out.find("\"plaza\": 1"), std::string::npos) << json.out;
}

TEST(Cli, RenderWritesPngOrSvgAndRefusesOtherExtensions) {
  const fs::path dir = testing::freshTempDir();
  const std::string map = str(testing::mapPath("cmu_campus.json"));
  EXPECT_EQ(runCli({"map", "render", map, "-o", str(dir / "campus.png")}).exit_code, 0);
  EXPECT_EQ(readFile(dir / "campus.png").substr(1, 3), "PNG");
  EXPECT_EQ(runCli({"map", "render", map, "-o", str(dir / "campus.svg"), "--width", "800"}).exit_code, 0);
  EXPECT_NE(readFile(dir / "campus.svg").find("<svg"), std::string::npos);
  const auto bad = runCli({"map", "render", map, "-o", str(dir / "campus.txt")});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.err.find(".png or .svg"), std::string::npos) << bad.err;
  EXPECT_FALSE(fs::exists(dir / "campus.txt"));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 2) << "no temporary files left";
}

TEST(Cli, GeoJsonExportThenImportGivesTheSameMap) {
  const fs::path dir = testing::freshTempDir();
  const std::string map = str(testing::mapPath("park_path.json"));
  const auto exported = runCli({"map", "export-geojson", map, "-o", str(dir / "park.geojson")});
  ASSERT_EQ(exported.exit_code, 0) << exported.err;
  const auto imported = runCli({"map", "import-geojson", str(dir / "park.geojson"), "-o", str(dir / "park.json")});
  ASSERT_EQ(imported.exit_code, 0) << imported.err;
  const MapData a = loadMap(testing::mapPath("park_path.json")).data();
  const MapData b = loadMap(dir / "park.json").data();
  ASSERT_EQ(a.roads.size(), b.roads.size());
  for (std::size_t i = 0; i < a.roads.size(); ++i) {
    ASSERT_EQ(a.roads[i].centerline.size(), b.roads[i].centerline.size());
    for (std::size_t k = 0; k < a.roads[i].centerline.size(); ++k) {
      EXPECT_LT((a.roads[i].centerline.points()[k] - b.roads[i].centerline.points()[k]).norm(), 1e-3);
    }
  }
}

TEST(Cli, ImportOfAnInvalidGeoJsonWritesNothing) {
  const fs::path dir = testing::freshTempDir();
  const auto r = runCli({"map", "import-geojson", str(testing::fixturePath("malformed/polygon_not_closed.geojson")), "-o",
                         str(dir / "out.json")});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("/features/0/geometry/coordinates/0: error: geojson.position"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out.json"));
}

// Point features with a `landmark` property import as landmarks, counted; `map info`
// counts them by kind; a landmark of an unknown kind is an error naming the file and the pointer.
TEST(Cli, GeoJsonLandmarksImportCountedAndAnUnknownKindIsNamed) {
  const fs::path dir = testing::freshTempDir();
  const auto r = runCli({"map", "import-geojson", str(testing::fixturePath("maps/valid/landmarks_each_kind.geojson")), "-o",
                         str(dir / "lm.json")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("(2 intersections, 1 roads, 5 landmarks)\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  assumed: 3 landmarks without a radius or a height: their kind's size\n"), std::string::npos) << r.out;
  const auto info = runCli({"map", "info", str(dir / "lm.json")});
  EXPECT_NE(info.out.find("landmarks:     5 (bench 1, bollard 1, manhole 1, pole 1, tree 1)\n"), std::string::npos) << info.out;
  const auto exported = runCli({"map", "export-geojson", str(dir / "lm.json"), "-o", str(dir / "lm.geojson")});
  EXPECT_NE(exported.out.find("(8 features)"), std::string::npos) << exported.out;
  const std::string bad = str(testing::fixturePath("malformed/landmark_unknown_kind.geojson"));
  const auto b = runCli({"map", "import-geojson", bad, "-o", str(dir / "bad.json")});
  EXPECT_EQ(b.exit_code, 1);
  EXPECT_NE(b.err.find(bad + ":/features/4/properties/landmark: error: schema.enum: unknown landmark kind \"lamppost\""),
            std::string::npos)
      << b.err;
  EXPECT_FALSE(fs::exists(dir / "bad.json"));
}

TEST(Cli, PredictAtTheDialoguesStartSeesR1WithParallelEdgesOneWidthApart) {
  const fs::path dir = testing::freshTempDir();
  const std::string map = str(testing::mapPath("cmu_campus.json"));
  const std::string camera = str(testing::mapPath("cameras/terregator_pinhole.json"));
  const auto r = runCli({"predict", "--map", map, "--camera", camera, "--at", "R1@I1+3", "--json", "-o", str(dir / "view.png")});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto j = nlohmann::json::parse(r.out);
  const auto& view = j["view"];  // the PredictedObject token, as the trace writes it
  ASSERT_EQ(view["regions"].size(), 1u);
  EXPECT_EQ(view["regions"][0]["id"], "R1");
  EXPECT_EQ(view["regions"][0]["kind"], "straight road");
  std::set<std::string> ids, world_ids;
  for (const auto& s : view["segments"]) {
    EXPECT_EQ(s["owner"], "R1");
    ids.insert(s["id"]);
  }
  EXPECT_EQ(ids, (std::set<std::string>{"R1.left.0", "R1.right.0"}));
  for (const auto& s : j["world"]["segments"]) world_ids.insert(s["id"]);
  EXPECT_EQ(world_ids, ids);
  const double width = testing::campusMap().road("R1").width;
  ASSERT_EQ(view["relations"].size(), 1u);
  EXPECT_EQ(view["relations"][0]["type"], "parallel");
  EXPECT_NEAR(view["relations"][0]["separation_m"].get<double>(), width, 1e-3);
  // The world block is the same segments in the map's frame: the pose carries each vehicle point there.
  const Pose2 pose(j["pose"]["x"].get<double>(), j["pose"]["y"].get<double>(), degToRad(j["pose"]["heading_deg"].get<double>()));
  ASSERT_EQ(j["world"]["segments"].size(), view["segments"].size());
  for (std::size_t i = 0; i < view["segments"].size(); ++i) {
    EXPECT_EQ(j["world"]["segments"][i]["id"], view["segments"][i]["id"]);
    for (int end = 0; end < 2; ++end) {
      const auto& v = view["segments"][i]["vehicle"][end];
      const auto& w = j["world"]["segments"][i]["world"][end];
      const Vec2 moved = pose.transform(Vec2(v[0].get<double>(), v[1].get<double>()));
      EXPECT_NEAR(moved.x(), w[0].get<double>(), 1e-3);
      EXPECT_NEAR(moved.y(), w[1].get<double>(), 1e-3);
    }
  }
  // The pose is 3 m from I1 along R1, facing away from it.
  const Vec2 i1 = testing::campusMap().intersection("I1").position;
  EXPECT_NEAR(std::hypot(j["pose"]["x"].get<double>() - i1.x(), j["pose"]["y"].get<double>() - i1.y()), 3.0, 1e-3);
  EXPECT_EQ(readFile(dir / "view.png").substr(1, 3), "PNG");
}

TEST(Cli, PredictSpeaksTheDialogueWithoutJson) {
  const auto r = runCli({"predict", "--map", str(testing::mapPath("cmu_campus.json")), "--camera",
                         str(testing::mapPath("cameras/terregator_fisheye.json")), "--pose", "50,30,90"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("Vision will see"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("cross intersection I1"), std::string::npos) << r.out;
}

TEST(Cli, PredictRefusesBadPositionsAndCameras) {
  const std::string map = str(testing::mapPath("cmu_campus.json"));
  const std::string camera = str(testing::mapPath("cameras/terregator_pinhole.json"));
  struct Case {
    std::vector<std::string> args;
    int exit_code;
    std::string message;
  };
  const fs::path dir = testing::freshTempDir();
  writeFileAtomic(dir / "bad_camera.json", std::string_view(R"({"format": "mapnav-camera/1", "model": "pinhole"})"));
  const std::vector<Case> cases{
      {{"--at", "R1@I1"}, 1, "expected ROAD@NODE+METERS"},  // malformed values: wrong input
      {{"--pose", "1,2"}, 1, "expected X,Y,HEADING_DEG"},
      {{}, 2, "needs the vehicle's pose"},  // a missing argument: usage
      {{"--at", "R99@I1+3"}, 1, "no road \"R99\""},
      {{"--at", "R1@I3+3"}, 1, "I3 is not an end of R1"},
      {{"--at", "R1@I1+3000"}, 1, "beyond the road's"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args{"predict", "--map", map, "--camera", camera};
    args.insert(args.end(), c.args.begin(), c.args.end());
    const auto r = runCli(args);
    EXPECT_EQ(r.exit_code, c.exit_code) << c.message;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << r.err;
  }
  const auto bad = runCli({"predict", "--map", map, "--camera", str(dir / "bad_camera.json"), "--at", "R1@I1+3"});
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find("bad_camera.json: error: schema.required"), std::string::npos) << bad.err;
}

TEST(Cli, RouteSpeaksTheDialogueAndPrintsJsonLegs) {
  const std::string map = str(testing::mapPath("cmu_campus.json"));
  const auto text = runCli({"route", "--map", map, "--from", "R1@I1+3", "--to", "R3@I3+2"});
  ASSERT_EQ(text.exit_code, 0) << text.err;
  EXPECT_EQ(text.out.substr(0, 59), "Drive on R1 3.0 m and turn right 90 degrees at I1 onto R2.\n");
  const auto json = runCli({"route", "--map", map, "--from", "R1@I1+3", "--to", "R3@I3+2", "--json"});
  ASSERT_EQ(json.exit_code, 0) << json.err;
  const auto j = nlohmann::json::parse(json.out);
  EXPECT_EQ(j["legs"][0], nlohmann::json::parse(R"({"action": "drive", "road": "R1", "meters": 3.0})"));
  EXPECT_EQ(j["legs"][1], nlohmann::json::parse(R"({"action": "turn", "at": "I1", "direction": "right", "degrees": 90.0, "onto": "R2"})"));
  EXPECT_EQ(j["legs"].back()["road"], "R3");
}

TEST(Cli, RouteWritesAPictureOrGeoJsonAndBlocksWhatItIsTold) {
  const fs::path dir = testing::freshTempDir();
  const std::string map = str(testing::mapPath("cmu_campus.json"));
  ASSERT_EQ(runCli({"route", "--map", map, "--from", "R1@I1+3", "--to", "R3@I3+2", "-o", str(dir / "r.png")}).exit_code, 0);
  EXPECT_EQ(readFile(dir / "r.png").substr(1, 3), "PNG");
  ASSERT_EQ(runCli({"route", "--map", map, "--from", "R1@I1+3", "--to", "R3@I3+2", "-o", str(dir / "r.geojson")}).exit_code, 0);
  const auto geo = nlohmann::json::parse(readFile(dir / "r.geojson"));
  EXPECT_EQ(geo["features"][0]["geometry"]["type"], "LineString");
  const auto detour = runCli({"route", "--map", map, "--from", "R1@I1+3", "--to", "R3@I3+2", "--block", "I2,R5", "--json"});
  ASSERT_EQ(detour.exit_code, 0) << detour.err;
  const auto route = nlohmann::json::parse(detour.out);  // named: a temporary's ["legs"] dies before the loop
  for (const auto& leg : route["legs"]) {
    EXPECT_NE(leg.value("road", ""), "R5");
    EXPECT_NE(leg.value("at", ""), "I2");
  }
}

TEST(Cli, RouteThatCannotBeFoundExitsOneWithTheReason) {
  const std::string map = str(testing::mapPath("cmu_campus.json"));
  const auto blocked = runCli({"route", "--map", map, "--from", "R1@I1+3", "--to", "R3@I3+2", "--block", "R3"});
  EXPECT_EQ(blocked.exit_code, 1);
  EXPECT_EQ(blocked.err, "mapnav: error: no route: the goal road R3 is blocked\n");
  const auto unknown = runCli({"route", "--map", map, "--from", "R1@I1+3", "--to", "R3@I3+2", "--block", "R404"});
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_NE(unknown.err.find("R404"), std::string::npos) << unknown.err;
  EXPECT_EQ(runCli({"route", "--map", map, "--from", "R1", "--to", "R3@I3+2"}).exit_code, 1);  // as its help says
  EXPECT_EQ(runCli({"route", "--map", map, "--from", "R1@I1+3", "--to", "R3@I3+2", "-o", "x.txt"}).exit_code, 2);
}

TEST(Cli, SimulateThenInspectTheLog) {
  const fs::path dir = testing::freshTempDir();
  const std::string mission = str(testing::mapPath("missions/campus_dialogue.json"));
  const auto sim = runCli({"simulate", "--mission", mission, "-o", str(dir / "log"), "--max-frames", "4", "--seed", "3"});
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  EXPECT_NE(sim.out.find("4 frames"), std::string::npos) << sim.out;
  const auto info = runCli({"log", "info", str(dir / "log"), "--json"});
  ASSERT_EQ(info.exit_code, 0) << info.err;
  EXPECT_EQ(nlohmann::json::parse(info.out)["frames"], 4);
  const auto frame = runCli({"log", "frame", str(dir / "log"), "2", "-o", str(dir / "f2.png")});
  ASSERT_EQ(frame.exit_code, 0) << frame.err;
  EXPECT_EQ(readFile(dir / "f2.png").substr(1, 3), "PNG");
  EXPECT_EQ(runCli({"log", "frame", str(dir / "log"), "9", "-o", str(dir / "f9.png")}).exit_code, 1);
  EXPECT_FALSE(fs::exists(dir / "f9.png"));
  // Writing over a log that is there is refused, and leaves it as it was.
  const auto again = runCli({"simulate", "--mission", mission, "-o", str(dir / "log"), "--max-frames", "1"});
  EXPECT_EQ(again.exit_code, 2);
  EXPECT_EQ(nlohmann::json::parse(runCli({"log", "info", str(dir / "log"), "--json"}).out)["frames"], 4);
}

TEST(Cli, ABadMissionExitsOneNamingTheProblem) {
  const fs::path dir = testing::freshTempDir();
  writeFileAtomic(dir / "m.json", std::string_view(R"({"format": "mapnav-mission/1", "map": "x.json", "camera": "y.json", "start": "R1@I1+3", "goal": "R3@I3+2"})"));
  const auto r = runCli({"simulate", "--mission", str(dir / "m.json"), "-o", str(dir / "log")});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("m.json:/map: error: mission.missing_file"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "log"));
  // A mission whose world and odometry blocks are wrong: every bad member, named by the file and its
  // pointer, the mission's numbers too.
  nlohmann::json mission = nlohmann::json::parse(readFile(testing::fixturePath("missions/short_crossing.json")));
  for (const char* key : {"map", "camera"})
    mission[key] = (testing::fixturePath("missions") / mission[key].get<std::string>()).string();
  mission["world"] = {{"shadow_k", 2}, {"shadw", 1}};
  mission["odometry"] = {{"gyro_bias_deg_s", 20}};
  writeFileAtomic(dir / "blocks.json", std::string_view(mission.dump()));
  const auto blocks = runCli({"simulate", "--mission", str(dir / "blocks.json"), "-o", str(dir / "log")});
  EXPECT_EQ(blocks.exit_code, 1);
  for (const std::string line :
       {":/world/shadow_k: error: schema.range: option shadow_k = 2: must be in (0, 1]",
        ":/world/shadw: error: schema.unknown_field: unknown option \"shadw\"",
        ":/odometry/gyro_bias_deg_s: error: schema.range: option gyro_bias_deg_s = 20: must be in [-10, 10]"})
    EXPECT_NE(blocks.err.find(str(dir / "blocks.json") + line), std::string::npos) << blocks.err;
  mission.erase("world");
  mission.erase("odometry");
  mission["speed_mps"] = 50;
  writeFileAtomic(dir / "numbers.json", std::string_view(mission.dump()));
  const auto numbers = runCli({"simulate", "--mission", str(dir / "numbers.json"), "-o", str(dir / "log")});
  EXPECT_EQ(numbers.exit_code, 1);
  EXPECT_NE(numbers.err.find(str(dir / "numbers.json") + ":/speed_mps: error: schema.range: option speed_mps = 50: must be in [0.01, 40]"),
            std::string::npos)
      << numbers.err;
  EXPECT_FALSE(fs::exists(dir / "log"));
}

TEST(Cli, VisionCommandsOnASimulatedFrame) {
  const fs::path dir = testing::freshTempDir();
  const std::string map = str(testing::mapPath("cmu_campus.json"));
  const std::string camera = str(testing::mapPath("cameras/terregator_pinhole.json"));
  ASSERT_EQ(runCli({"simulate", "--mission", str(testing::mapPath("missions/campus_dialogue.json")), "-o", str(dir / "log"),
                    "--max-frames", "1"})
                .exit_code,
            0);
  const std::string frame = str(dir / "log/images/000000.png");
  // The first frame is taken at the mission's start, R1@I1+3, facing I1 (the route's direction).
  const auto names = runCli({"pipelines", "--names"});
  EXPECT_EQ(names.exit_code, 0);
  EXPECT_NE(names.out.find("sidewalk\n"), std::string::npos) << names.out;
  const auto detect = runCli({"detect", "--map", map, "--camera", camera, "--pose", "53,40,180", frame, "--json", "-o", str(dir / "d.png")});
  ASSERT_EQ(detect.exit_code, 0) << detect.err;
  const auto j = nlohmann::json::parse(detect.out);
  EXPECT_EQ(j["status"], "ok");
  EXPECT_GE(j["region_image"].size(), 3u);
  EXPECT_EQ(readFile(dir / "d.png").substr(1, 3), "PNG");
  const auto segment = runCli({"segment", "--map", map, "--camera", camera, "--pose", "53,40,180", frame, "-o", str(dir / "mask.png")});
  ASSERT_EQ(segment.exit_code, 0) << segment.err;
  const auto rectify = runCli({"rectify", frame, "--camera", camera, "-o", str(dir / "top.png")});
  ASSERT_EQ(rectify.exit_code, 0) << rectify.err;
  EXPECT_EQ(runCli({"detect", "--pipeline", "nope", "--map", map, "--camera", camera, "--pose", "53,40,180", frame}).exit_code, 1);
  EXPECT_EQ(runCli({"detect", "--map", map, "--camera", camera, frame}).exit_code, 2);  // no pose
}

TEST(Cli, CalibrateTiltFromTwoGroundParallelLinesAndSegmentFromAGivenRegion) {
  const std::string camera_file = str(testing::mapPath("cameras/terregator_pinhole.json"));
  const auto camera = testing::terregatorPinhole();  // the same camera: 22 degrees down
  auto line = [&](double y) {
    const Vec2 a = *camera->projectGround(Vec2(3, y)), b = *camera->projectGround(Vec2(11, y));
    char text[128];
    std::snprintf(text, sizeof text, "%.6f,%.6f,%.6f,%.6f", a.x(), a.y(), b.x(), b.y());
    return std::string(text);
  };
  const auto tilt = runCli({"calibrate", "tilt", "--camera", camera_file, "--line", line(1.25), "--line", line(-1.25)});
  ASSERT_EQ(tilt.exit_code, 0) << tilt.err;
  EXPECT_NE(tilt.out.find("tilt 22.000 degrees"), std::string::npos) << tilt.out;

  const fs::path dir = testing::freshTempDir();
  ASSERT_EQ(runCli({"simulate", "--mission", str(testing::mapPath("missions/campus_dialogue.json")), "-o", str(dir / "log"),
                    "--max-frames", "1"})
                .exit_code,
            0);
  // A trapezoid on the sidewalk straight ahead, as a person would draw it.
  const auto seg = runCli({"segment", str(dir / "log/images/000000.png"), "--camera", camera_file, "--train-region",
                           "200,470;310,470;270,300;240,300", "-o", str(dir / "mask.png")});
  ASSERT_EQ(seg.exit_code, 0) << seg.err;
  EXPECT_EQ(readFile(dir / "mask.png").substr(1, 3), "PNG");
  EXPECT_EQ(runCli({"segment", str(dir / "log/images/000000.png"), "--camera", camera_file, "--train-region", "1,2;3",
                    "-o", str(dir / "bad.png")})
                .exit_code,
            1);  // a malformed polygon: wrong input
}

}  // namespace
}  // namespace mapnav

namespace mapnav {
namespace {

TEST(Cli, ReplayRunAndTraceShowEndToEnd) {
  const fs::path dir = testing::freshTempDir();
  const std::string mission = str(testing::fixturePath("missions/short_crossing.json"));
  ASSERT_EQ(runCli({"simulate", "--mission", mission, "-o", str(dir / "log")}).exit_code, 0);

  const auto json_run = runCli({"replay", "--mission", mission, "--log", str(dir / "log"), "--json"});
  EXPECT_EQ(json_run.exit_code, 0) << json_run.err;
  EXPECT_EQ(json_run.err, "");  // no progress bar when stderr is not a terminal
  const auto j = nlohmann::ordered_json::parse(json_run.out);
  const std::vector<std::string> keys = {"frames", "reached_goal", "lateral_rms_m", "along_rms_m", "heading_rms_deg",
                                         "max_error_m", "odometry_only_max_error_m", "vision_failures", "replans",
                                         "latency_ms_median", "latency_ms_p99", "along_after_intersection_max_m"};
  std::vector<std::string> first;
  for (auto it = j.begin(); it != j.end() && first.size() < keys.size(); ++it) first.push_back(it.key());
  EXPECT_EQ(first, keys);
  EXPECT_EQ(j["reached_goal"], true);
  EXPECT_LE(j["lateral_rms_m"].get<double>(), 0.05);
  EXPECT_LE(j["heading_rms_deg"].get<double>(), 0.5);

  const std::string trace = str(dir / "trace.jsonl");
  const auto text_run = runCli({"replay", "--mission", mission, "--log", str(dir / "log"), "--trace", trace});
  EXPECT_EQ(text_run.exit_code, 0) << text_run.err;
  EXPECT_NE(text_run.out.find("short crossing (replay, pipeline sidewalk): goal reached"), std::string::npos) << text_run.out;
  EXPECT_NE(text_run.out.find("odometry alone:"), std::string::npos);
  EXPECT_NE(text_run.out.find("loop latency (512x480): median"), std::string::npos);
  EXPECT_NE(text_run.out.find("wrote " + trace), std::string::npos);
  // Path agreement, with the log's truth: Vision's road holds the vehicle's future path in every
  // measured frame; the last frames have less than 7 m of the log ahead.
  const auto& p = j["path_agreement"];
  ASSERT_TRUE(p.is_object()) << json_run.out;
  EXPECT_EQ(p["frames"], j["frames"]);
  EXPECT_EQ(p["measured"].get<int>() + p["unmeasured"]["path_too_short"].get<int>(), j["frames"].get<int>()) << p.dump();
  EXPECT_GT(p["measured"].get<int>(), 0);
  EXPECT_EQ(p["inside_goal_frames"], p["measured"]) << p.dump();
  EXPECT_EQ(p["median_inside"], 1.0);
  EXPECT_EQ(p["centre_line_frames"], 0);  // sidewalk gives no centre line
  EXPECT_EQ(p["angle_goal_fraction"], nullptr);
  EXPECT_NE(text_run.out.find("  path agreement (the true future path 2-15 m ahead, from the log's truth):\n"
                              "    road found holds >= 95 % of the path in " + std::to_string(p["measured"].get<int>()) +
                              " of " + std::to_string(p["measured"].get<int>()) + " (1.000) measured frames"),
            std::string::npos)
      << text_run.out;

  // The same log without its truth: path agreement is not measured (null), not 0.
  fs::create_directories(dir / "no-truth");
  fs::copy(dir / "log", dir / "no-truth", fs::copy_options::recursive);
  const std::string frames = readFile(dir / "log" / "frames.jsonl");
  std::string stripped;
  for (std::size_t at = 0, truth; at < frames.size(); at = frames.find('}', truth) + 1) {
    truth = frames.find(",\"truth\":{", at);
    stripped += frames.substr(at, truth - at);
    if (truth == std::string::npos) break;
  }
  ASSERT_EQ(stripped.find("truth"), std::string::npos);
  writeFileAtomic(dir / "no-truth" / "frames.jsonl", stripped);
  const auto blind = runCli({"replay", "--mission", mission, "--log", str(dir / "no-truth"), "--json"});
  ASSERT_EQ(blind.err, "");
  const auto b = nlohmann::ordered_json::parse(blind.out);
  EXPECT_EQ(b["frames"], j["frames"]);
  EXPECT_TRUE(b.contains("path_agreement"));
  EXPECT_EQ(b["path_agreement"], nullptr);
  EXPECT_EQ(b["lateral_rms_m"], nullptr);
  const auto blind_text = runCli({"replay", "--mission", mission, "--log", str(dir / "no-truth")});
  EXPECT_NE(blind_text.out.find("no ground truth: errors and path agreement not measured"), std::string::npos)
      << blind_text.out;
  EXPECT_EQ(blind_text.out.find("path agreement ("), std::string::npos) << blind_text.out;

  const auto show = runCli({"trace", "show", trace});
  EXPECT_EQ(show.exit_code, 0) << show.err;
  EXPECT_EQ(show.out.rfind("User: Robot is at road R2, 30 meters from I1.", 0), 0u) << show.out.substr(0, 200);
  EXPECT_NE(show.out.find("Navigator: Drive on R2 10.0 meters and go straight through I2."), std::string::npos);
  EXPECT_NE(show.out.find("Map: Vision will see straight road"), std::string::npos);
  EXPECT_NE(show.out.find("Mission: goal reached"), std::string::npos);

  const auto run = runCli({"run", "--mission", mission, "--max-frames", "4", "--json", "--seed", "3"});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  const auto r = nlohmann::json::parse(run.out);
  EXPECT_EQ(r["frames"], 4);
  EXPECT_EQ(r["mode"], "closed-loop");
  EXPECT_EQ(r["reached_goal"], false);
  // Four frames, under a metre: no frame has 7 m of the simulator's truth after it.
  EXPECT_EQ(r["path_agreement"]["measured"], 0);
  EXPECT_EQ(r["path_agreement"]["unmeasured"]["path_too_short"], 4);
  EXPECT_EQ(r["path_agreement"]["median_inside"], nullptr);
  EXPECT_EQ(r["path_agreement"]["inside_goal_fraction"], nullptr);
}

TEST(Cli, MissionRunnerErrorsExitOneOrTwoWithAMessage) {
  const fs::path dir = testing::freshTempDir();
  const std::string mission = str(testing::fixturePath("missions/short_crossing.json"));
  ASSERT_EQ(runCli({"simulate", "--mission", mission, "-o", str(dir / "log"), "--max-frames", "6"}).exit_code, 0);
  // A log that ends before the goal: the mission failed.
  const auto short_log = runCli({"replay", "--mission", mission, "--log", str(dir / "log")});
  EXPECT_EQ(short_log.exit_code, 1);
  EXPECT_NE(short_log.out.find("the log ended"), std::string::npos) << short_log.out;
  // An unknown pipeline: the input is wrong.
  const auto pipeline = runCli({"replay", "--mission", mission, "--log", str(dir / "log"), "--pipeline", "nope"});
  EXPECT_EQ(pipeline.exit_code, 1);
  EXPECT_NE(pipeline.err.find("mapnav: error: "), std::string::npos);
  EXPECT_NE(pipeline.err.find("nope"), std::string::npos) << pipeline.err;
  // Usage and I/O: no such log, no such mission, a missing trace file.
  EXPECT_EQ(runCli({"replay", "--mission", mission, "--log", str(dir / "nowhere")}).exit_code, 2);
  EXPECT_EQ(runCli({"run", "--mission", str(dir / "none.json")}).exit_code, 2);
  EXPECT_EQ(runCli({"replay", "--mission", mission}).exit_code, 2);
  const auto missing = runCli({"trace", "show", str(dir / "none.jsonl")});
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.err.find("mapnav: error: "), std::string::npos);
  // An invalid mission: its problems with their pointers.
  writeFileAtomic(dir / "bad.json", std::string_view(R"({"format": "mapnav-mission/1", "halt": {"resume_after_frames": -3}})"));
  const auto bad = runCli({"run", "--mission", str(dir / "bad.json")});
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.err.find(str(dir / "bad.json") + ":/halt/resume_after_frames: error: schema.range"), std::string::npos)
      << bad.err;
  // A trace with bad lines: FILE:LINE for each, exit 1.
  const std::string trace = str(dir / "bad.jsonl");
  writeFileAtomic(trace, std::string_view(
                             "{\"t\":0,\"frame\":null,\"module\":\"MotionControl\",\"type\":\"Executing\",\"payload\":"
                             "{\"sequence\":null,\"executes\":false,\"kind\":\"stop\"}}\n"
                             "garbage\n"
                             "{\"t\":1,\"frame\":0,\"module\":\"Navigator\",\"type\":\"MotionCommand\",\"payload\":{}}\n"));
  const auto show = runCli({"trace", "show", trace});
  EXPECT_EQ(show.exit_code, 1);
  EXPECT_NE(show.err.find(trace + ":2:1: error: trace.not_json: not JSON"), std::string::npos) << show.err;
  EXPECT_NE(show.err.find(trace + ":3:1: error: trace.field: /payload/kind: missing"), std::string::npos) << show.err;
  EXPECT_NE(show.err.find("mapnav: error: " + trace + ": invalid (2 errors)"), std::string::npos) << show.err;
}

TEST(Cli, MissionRunnerHelp) {
  for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
           {"replay", "--help"}, {"run", "--help"}, {"trace", "show", "--help"}}) {
    const auto r = runCli(args);
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("Usage"), std::string::npos);
  }
  EXPECT_NE(runCli({"replay", "--help"}).out.find("along_after_intersection_max_m"), std::string::npos);
}

}  // namespace
}  // namespace mapnav
