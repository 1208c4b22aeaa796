#include "mapnav/map/validation.h"

#include <gtest/gtest.h>

#include <fstream>
#include <regex>
#include <set>

#include "map_fixtures.h"
#include "mapnav/core/error.h"
#include "mapnav/core/io.h"
#include "mapnav/core/json.h"
#include "mapnav/map/map_io.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {
namespace fs = std::filesystem;

std::vector<fs::path> invalidFixtures() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(testing::fixturePath("maps/invalid"))) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

// Each fixture names the one problem it has: {"x-expect": {"check", "where"}}.
TEST(InvalidMapFixtures, EachReportsItsCheckAtTheExactPointerAndNothingElse) {
  const auto files = invalidFixtures();
  ASSERT_GE(files.size(), 20u);
  const std::set<std::string> warnings{"topology.disconnected", "roads.very_short", "intersections.kind_mismatch",
                                       "landmarks.on_paved_area", "landmarks.far_from_road"};
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.filename().string());
    const Json expect = Json::parse(readFile(file))["x-expect"];
    const std::string check = expect["check"], where = expect["where"];
    Issues issues;
    const auto map = loadMap(file, issues);
    ASSERT_EQ(issues.size(), 1u) << formatIssue(issues.at(0), file.string());
    EXPECT_EQ(issues[0].check, check);
    EXPECT_EQ(issues[0].where, where);
    EXPECT_FALSE(issues[0].message.empty());
    const bool is_warning = warnings.contains(check);
    EXPECT_EQ(issues[0].severity, is_warning ? Severity::Warning : Severity::Error);
    EXPECT_EQ(map.has_value(), is_warning) << "a map with only warnings loads; one with an error does not";
  }
}

// The doc's table of checks and the fixtures must not drift apart.
TEST(InvalidMapFixtures, EveryDocumentedCheckHasAFixture) {
  const std::string doc = readFile(testing::sourceDir() / "docs" / "map-format.md");
  const std::regex row(R"(\n\| `([a-z_]+\.[a-z_]+)` \| (error|warning) \|)");
  std::set<std::string> documented;
  for (auto it = std::sregex_iterator(doc.begin(), doc.end(), row); it != std::sregex_iterator(); ++it) {
    documented.insert((*it)[1]);
  }
  ASSERT_GE(documented.size(), 24u);
  std::set<std::string> covered;
  for (const fs::path& file : invalidFixtures()) covered.insert(file.stem().string());
  for (const std::string& check : documented) {
    // Syntax errors and the too-many-errors cap are exercised by the core and CLI tests.
    if (check.rfind("json.", 0) == 0 || check == "schema.too_many_errors") continue;
    EXPECT_TRUE(covered.contains(check)) << "no fixture tests/data/maps/invalid/" << check << ".json";
  }
}

TEST(ExampleMaps, AreValidWithoutWarnings) {
  for (const char* name : {"cmu_campus.json", "park_path.json"}) {
    Issues issues;
    EXPECT_TRUE(loadMap(testing::mapPath(name), issues)) << name;
    for (const Issue& issue : issues) ADD_FAILURE() << formatIssue(issue, name);
  }
}

TEST(ValidateMap, ReportsEveryProblemInOnePass) {
  MapData data = testing::crossOfFourRoads();
  data.roads[0].to = "nowhere";
  data.roads[1].surface = "lava";
  data.roads[2].width = std::numeric_limits<double>::quiet_NaN();
  data.intersections[4].position = Vec2(std::numeric_limits<double>::infinity(), 0);
  const Issues issues = validateMap(data);
  std::vector<std::pair<std::string, std::string>> got;
  for (const Issue& issue : issues) got.emplace_back(issue.check, issue.where);
  const std::vector<std::pair<std::string, std::string>> expected{
      {"geometry.invalid_coordinate", "/intersections/4/position"},
      {"roads.unknown_intersection", "/roads/0/to"},
      {"surfaces.unknown", "/roads/1/surface"},
      {"roads.invalid_width", "/roads/2/width"},
      // R1 no longer reaches the dead end E, so E has no road and falls off the network.
      {"intersections.kind_mismatch", "/intersections/1/kind"},
      {"topology.disconnected", "/intersections/1"},
  };
  EXPECT_EQ(got, expected);
}

TEST(ValidateMap, RoadsTouchingAtTheirSharedIntersectionAreNotACrossing) {
  // The cross: four roads all meet at I1's position, which is not a crossing.
  EXPECT_TRUE(validateMap(testing::crossOfFourRoads()).empty());
}

TEST(ValidateMap, ARoadPassingThroughAnIntersectionItDoesNotEndAtIsACrossing) {
  MapData data = testing::crossOfFourRoads();
  // R1 now runs from W's side straight through I1 to E without ending there.
  data.roads[0].from = "W";
  data.roads[0].centerline = Polyline2({Vec2(-20, 0), Vec2(20, 0)});
  const Issues issues = validateMap(data);
  ASSERT_FALSE(issues.empty());
  bool found = false;
  for (const Issue& issue : issues) found = found || issue.check == "roads.crossing_without_intersection";
  EXPECT_TRUE(found);
}

// Lengths and widths a hair from the limit: the message prints enough digits that the numbers read
// in the order the comparison says (not "1.00 m long (< 1.00 m)").
TEST(ValidateMap, NumbersInMessagesNeverContradictTheComparison) {
  MapData data = testing::crossOfFourRoads();
  data.roads[0].centerline = Polyline2({Vec2(0, 0), Vec2(0.9996, 0)});
  data.intersections[1].position = Vec2(0.9996, 0);  // E
  ASSERT_EQ(data.intersections[1].id, "E");
  ValidationOptions options;
  data.roads[1].width = options.max_width_m + 0.001;
  std::map<std::string, std::string> messages;
  for (const Issue& issue : validateMap(data, options)) messages[issue.check] = issue.message;
  EXPECT_EQ(messages["roads.very_short"], "road \"R1\" is 0.9996 m long (< 1.0000 m)");
  EXPECT_EQ(messages["roads.invalid_width"], "width 100.001 m must be > 0 and <= 100.000 m");
}

TEST(ValidateMap, ALoopRoadBackToItsStartIsNotASelfIntersectionButAFigureEightIs) {
  // A lollipop, as OpenStreetMap has them: a loop leaving E and coming back to it.
  MapData data = testing::crossOfFourRoads();
  for (Intersection& x : data.intersections) {
    if (x.id == "E") x.kind = IntersectionKind::Other;
  }
  Road loop = data.roads[0];
  loop.id = "LOOP";
  loop.from = loop.to = "E";
  loop.centerline = Polyline2({Vec2(20, 0), Vec2(30, -5), Vec2(40, 0), Vec2(30, 5), Vec2(20, 0)});
  data.roads.push_back(loop);
  auto checks = [](const Issues& issues) {
    std::multiset<std::string> out;
    for (const Issue& i : issues) out.insert(i.check);
    return out;
  };
  EXPECT_EQ(checks(validateMap(data)).count("roads.self_intersection"), 0u);
  // The same loop drawn as a figure eight: segments 1 and 3 cross at (35, 0).
  data.roads.back().centerline = Polyline2({Vec2(20, 0), Vec2(30, 5), Vec2(40, -5), Vec2(40, 5), Vec2(30, -5), Vec2(20, 0)});
  const Issues issues = validateMap(data);
  ASSERT_EQ(checks(issues).count("roads.self_intersection"), 1u);
  for (const Issue& i : issues) {
    if (i.check == "roads.self_intersection") {
      EXPECT_EQ(i.where, "/roads/4/centerline/1");
    }
  }
}

TEST(ValidateMap, EndInsideAnAuthoredShapeIsAtTheIntersection) {
  MapData data = testing::crossOfFourRoads();
  // A 6 m plaza square; R1 now starts at its edge, 2.9 m from the position.
  data.intersections[0].shape = Polygon2{{-3, -3}, {3, -3}, {3, 3}, {-3, 3}};
  data.roads[0].centerline = Polyline2({Vec2(2.9, 0), Vec2(20, 0)});
  EXPECT_TRUE(validateMap(data).empty());
  data.roads[0].centerline = Polyline2({Vec2(3.6, 0), Vec2(20, 0)});  // 0.6 m outside: beyond 0.5 m
  const Issues issues = validateMap(data);
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].check, "roads.end_far_from_intersection");
  EXPECT_EQ(issues[0].where, "/roads/0/centerline/0");
}

TEST(ValidationOptions, DefaultsAreValidAndBadFieldsAreNamed) {
  EXPECT_NO_THROW(ValidationOptions{}.validate());
  ValidationOptions options;
  options.end_tolerance_m = -1;
  try {
    options.validate();
    FAIL();
  } catch (const InvalidInput& e) {
    EXPECT_EQ(std::string(e.what()), "ValidationOptions::end_tolerance_m = -1: must be finite and >= 0");
  }
  options = {};
  options.max_width_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(options.validate(), InvalidInput);
}

}  // namespace
}  // namespace mapnav

namespace mapnav {
namespace {

// The options a caller loads with are the ones the Map is held to (no second, stricter pass).
TEST(LoadMap, UsesTheCallersValidationOptionsOnce) {
  const auto file = testing::fixturePath("maps/invalid/roads.end_far_from_intersection.json");  // an end 2 m off
  Issues strict;
  EXPECT_FALSE(loadMap(file, strict));
  ValidationOptions loose;
  loose.end_tolerance_m = 2.5;
  Issues issues;
  const auto map = loadMap(file, issues, loose);
  ASSERT_TRUE(map);
  EXPECT_TRUE(issues.empty());
  EXPECT_TRUE(map->warnings().empty());
}

TEST(LoadMap, KeepsWarningsOnTheMap) {
  Issues issues;
  const auto map = loadMap(testing::fixturePath("maps/invalid/roads.very_short.json"), issues);
  ASSERT_TRUE(map);
  ASSERT_EQ(map->warnings().size(), 1u);
  EXPECT_EQ(map->warnings()[0].check, "roads.very_short");
  EXPECT_EQ(issues, map->warnings());
}

}  // namespace
}  // namespace mapnav
