#include "mapnav/map/map_io.h"

#include <gtest/gtest.h>

#include <set>

#include "map_fixtures.h"
#include "mapnav/core/error.h"
#include "mapnav/map/validation.h"
#include "mapnav/core/io.h"
#include "mapnav/core/json.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

TEST(MapJson, LoadSaveLoadIsExactForEveryExampleMap) {
  for (const char* name : {"cmu_campus.json", "park_path.json"}) {
    SCOPED_TRACE(name);
    const Map first = loadMap(testing::mapPath(name));
    const auto path = testing::freshTempDir() / name;
    saveMap(first.data(), path);
    const Map second = loadMap(path);
    EXPECT_EQ(first.data(), second.data());  // every double to the bit
    EXPECT_EQ(mapToJson(first.data()), readFile(path));
  }
}

TEST(MapJson, RoundTripKeepsOptionalMembers) {
  MapData data = testing::crossOfFourRoads();
  data.schema = "schema/mapnav-map-1.schema.json";
  data.origin = GeoOrigin{40.4433, -79.9436, 280.5};
  data.roads[1].oneway = true;
  data.roads[2].cost_factor = 2.5;
  data.position_sigma_m = 0.5;
  data.roads[0].position_sigma_m = 2.0;
  data.roads[3].centerline = Polyline2({Vec2(0, 0), Vec2(0.1 + 0.2, -7.000000000000001), Vec2(0, -20)});
  data.intersections[0].shape = Polygon2{{-3, -3}, {3, -3}, {3, 3}, {-3, 3}};
  Issues issues;
  const auto back = parseMap(mapToJson(data), issues);
  ASSERT_TRUE(back);
  EXPECT_TRUE(issues.empty());
  EXPECT_EQ(*back, data);
}

// position_sigma_m: the map's, a road's own, and where either is out of range the issue at its pointer.
TEST(MapJson, PositionSigmaIsTheRoadsElseTheMapsAndOutOfRangeIsAnError) {
  MapData data = testing::crossOfFourRoads();
  EXPECT_EQ(data.position_sigma_m, 0.0);  // a mapnav map is exact unless it says
  data.position_sigma_m = 0.5;
  data.roads[1].position_sigma_m = 2.0;
  EXPECT_EQ(positionSigma(data, data.roads[0]), 0.5);
  EXPECT_EQ(positionSigma(data, data.roads[1]), 2.0);
  EXPECT_TRUE(validateMap(data).empty());
  data.position_sigma_m = -0.1;
  data.roads[1].position_sigma_m = 1000;
  const Issues issues = validateMap(data);
  ASSERT_EQ(issues.size(), 2u);
  EXPECT_EQ(issues[0].check, "schema.range");
  EXPECT_EQ(issues[0].where, "/position_sigma_m");
  EXPECT_EQ(issues[1].where, "/roads/1/position_sigma_m");
  EXPECT_EQ(issues[1].message, "position_sigma_m 1000 must be >= 0 and <= 100 m");
}

TEST(MapJson, RoundTripKeepsLandmarks) {
  MapData data = testing::crossOfFourRoads();
  data.landmarks = {Landmark{"T1", LandmarkKind::Tree, Vec2(10, 2.4), 0.2, 7.5, "R1", {{"osm_node", PropertyValue::json("42")}}},
                    Landmark{"M1", LandmarkKind::Manhole, Vec2(0.3, 12), 0.35, 0.0, "", {}}};
  Issues issues;
  const auto back = parseMap(mapToJson(data), issues);
  ASSERT_TRUE(back);
  EXPECT_TRUE(issues.empty());
  EXPECT_EQ(*back, data);
}

TEST(MapJson, ALandmarkWithoutASizeTakesItsKindsSize) {
  MapData data = testing::crossOfFourRoads();
  Json doc = Json::parse(mapToJson(data));
  doc["landmarks"] = Json::parse(R"([{"id": "B1", "kind": "bench", "position": [5, 2.5]},
                                     {"id": "P1", "kind": "pole", "position": [-5, 1.5], "height": 4.5}])");
  Issues issues;
  const auto back = parseMap(doc.dump(), issues);
  ASSERT_TRUE(back) << (issues.empty() ? "" : formatIssue(issues[0], "<map>"));
  ASSERT_EQ(back->landmarks.size(), 2u);
  EXPECT_EQ(back->landmarks[0].radius, 0.8);  // a bench: half its 1.6 m seat
  EXPECT_EQ(back->landmarks[0].height, 0.8);
  EXPECT_EQ(back->landmarks[0].road, "");
  EXPECT_EQ(back->landmarks[1].radius, 0.10);  // a lamp post's default radius, its own height
  EXPECT_EQ(back->landmarks[1].height, 4.5);
}

TEST(ParseMap, AnUnknownLandmarkKindNamesTheKindsThereAre) {
  Json doc = Json::parse(mapToJson(testing::crossOfFourRoads()));
  doc["landmarks"] = Json::parse(R"([{"id": "X1", "kind": "statue", "position": [5, 2.5]}])");
  Issues issues;
  EXPECT_FALSE(parseMap(doc.dump(), issues));
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].check, "schema.enum");
  EXPECT_EQ(issues[0].where, "/landmarks/0/kind");
  EXPECT_EQ(issues[0].message, "unknown landmark kind \"statue\"; expected one of pole, tree, bench, bollard, manhole");
}

TEST(MapJson, ReadsTheCampusAsAuthored) {
  const Map map = loadMap(testing::mapPath("cmu_campus.json"));
  EXPECT_EQ(map.name(), "CMU campus sidewalks");
  EXPECT_GE(map.intersections().size(), 12u);
  EXPECT_GE(map.roads().size(), 16u);
  EXPECT_EQ(map.intersection("I1").kind, IntersectionKind::Cross);
  EXPECT_EQ(map.intersection("I1").position, Vec2(50, 40));
  ASSERT_TRUE(map.data().origin);
  EXPECT_EQ(map.data().origin->lat, 40.4433);
  // The papers' dialogue: R1 touches I1, R3 touches I3.
  const Road& r1 = map.road("R1");
  const Road& r3 = map.road("R3");
  EXPECT_TRUE(r1.from == "I1" || r1.to == "I1");
  EXPECT_TRUE(r3.from == "I3" || r3.to == "I3");
  // Every kind of intersection is there.
  std::set<IntersectionKind> kinds;
  for (const Intersection& x : map.intersections()) kinds.insert(x.kind);
  for (IntersectionKind k : {IntersectionKind::Cross, IntersectionKind::T, IntersectionKind::Y, IntersectionKind::L,
                             IntersectionKind::Plaza, IntersectionKind::End}) {
    EXPECT_TRUE(kinds.contains(k)) << toString(k);
  }
}

TEST(MapJson, ParkPathIsAboutAKilometreWithTightBends) {
  const Map map = loadMap(testing::mapPath("park_path.json"));
  double length = 0;
  double min_radius = 1e9;
  for (const Road& road : map.roads()) {
    length += road.centerline.length();
    EXPECT_EQ(road.surface, "asphalt");
    // Radius of the circle through three consecutive points.
    const auto& p = road.centerline.points();
    for (std::size_t i = 1; i + 1 < p.size(); ++i) {
      const double a = (p[i] - p[i - 1]).norm(), b = (p[i + 1] - p[i]).norm(), c = (p[i + 1] - p[i - 1]).norm();
      const double area2 = std::abs(cross2(p[i] - p[i - 1], p[i + 1] - p[i - 1]));
      if (area2 > 1e-9) min_radius = std::min(min_radius, a * b * c / (2 * area2));
    }
  }
  EXPECT_GT(length, 900.0);
  EXPECT_LT(length, 1150.0);
  EXPECT_GT(min_radius, 12.0);
  EXPECT_LT(min_radius, 18.0);
}

TEST(ParseMap, CollectsEveryStructuralProblemWithItsPointer) {
  Issues issues;
  const auto map = parseMap(R"({"format": "mapnav-map/1", "name": "m", "surfaces": {"c": {"rgb": [1, 2], "spread": [0, 0, 0]}},
    "intersections": [{"id": "I1", "kind": "X", "position": [0, 0]}],
    "roads": [{"id": "R1", "from": "I1", "to": "I1", "centerline": [[0, 0], [1, "1"]], "width": 2,
               "surface": "c", "left": "c", "right": "c", "colour": "red"}]})",
                            issues);
  EXPECT_FALSE(map);
  std::vector<std::pair<std::string, std::string>> got;
  for (const Issue& issue : issues) got.emplace_back(issue.check, issue.where);
  const std::vector<std::pair<std::string, std::string>> expected{
      {"schema.type", "/surfaces/c/rgb"},
      {"schema.enum", "/intersections/0/kind"},
      {"schema.type", "/roads/0/centerline/1/1"},
      {"schema.unknown_field", "/roads/0/colour"},
  };
  EXPECT_EQ(got, expected);
}

TEST(ParseMap, AHugeArrayOfBadPointsGivesTwentyOnePlusOneLines) {
  std::string text = R"({"format": "mapnav-map/1", "name": "m", "surfaces": {}, "intersections": [], "roads": [
    {"id": "R1", "from": "a", "to": "b", "width": 1, "surface": "s", "left": "s", "right": "s", "centerline": [)";
  for (int i = 0; i < 100000; ++i) text += i ? ",null" : "null";
  text += "]}]}";
  Issues issues;
  EXPECT_FALSE(parseMap(text, issues));
  ASSERT_EQ(issues.size(), 21u);
  EXPECT_EQ(issues[19].where, "/roads/0/centerline/19");
  EXPECT_EQ(issues[20].check, "schema.too_many_errors");
  EXPECT_EQ(issues[20].message, "99980 more bad elements in this array are not listed");
}

TEST(LoadMap, ThrowsValidationErrorOrIoError) {
  EXPECT_THROW(loadMap(testing::fixturePath("maps/invalid/roads.unknown_intersection.json")), ValidationError);
  EXPECT_THROW(loadMap(testing::fixturePath("maps/does-not-exist.json")), IoError);
}

}  // namespace
}  // namespace mapnav
