#include "mapnav/navigator/route.h"

#include <gtest/gtest.h>

#include <random>

#include "mapnav/core/error.h"
#include "mapnav/map/generate.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

RoadPosition at(const std::string& text) { return parseRoadPosition(text); }

struct ExpectedLeg {
  std::string what;  // "drive R1 3" or "turn I1 right 90 R2"
};

// Legs as short strings, to compare whole routes at a glance.
std::vector<std::string> describe(const Route& route) {
  std::vector<std::string> out;
  char text[128];
  for (const Leg& leg : route.legs) {
    if (leg.action == LegAction::Drive) {
      std::snprintf(text, sizeof text, "drive %s %.1f", leg.road.c_str(), leg.meters);
    } else {
      std::snprintf(text, sizeof text, "turn %s %s %.0f %s", leg.at.c_str(), turnDirection(leg.angle).c_str(),
                    std::abs(radToDeg(leg.angle)), leg.road.c_str());
    }
    out.emplace_back(text);
  }
  return out;
}

// Wallace 1985, Figure 1: "Robot is at road R1, 3 meters from I1. Navigate to R3, 2 meters from
// I3." — "Drive on it 2.5 meters and turn to right 90 degrees."
TEST(CampusDialogue, RouteFromR1NearI1ToR3NearI3TurnsRightAtI1ThenLeftTwice) {
  const Map& map = testing::campusMap();
  RoadGraph graph(map);
  const RouteResult result = graph.route(at("R1@I1+3"), at("R3@I3+2"));
  ASSERT_TRUE(result.route) << result.reason;
  const Route& r = *result.route;
  // R1 runs east from I1, so the robot drives 3 m west to I1 and turns north (right) onto R2,
  // straight on through the cross I2 onto R4, bears left 30° onto the curved Y branch R5 at I4,
  // and at the L I3, arriving heading west, turns south (left 90°) onto R3.
  const double r5 = map.road("R5").centerline.length();
  char r5_leg[32];
  std::snprintf(r5_leg, sizeof r5_leg, "drive R5 %.1f", r5);
  const std::vector<std::string> expected{"drive R1 3.0", "turn I1 right 90 R2", "drive R2 40.0", "turn I2 straight 0 R4",
                                          "drive R4 20.0", "turn I4 left 30 R5",  r5_leg,          "turn I3 left 90 R3",
                                          "drive R3 2.0"};
  EXPECT_EQ(describe(r), expected);
  EXPECT_NEAR(r.length_m, 3 + 40 + 20 + r5 + 2, 1e-9);
  EXPECT_EQ(r.intersections, (std::vector<std::string>{"I1", "I2", "I4", "I3"}));
  EXPECT_NEAR(r.line.length(), r.length_m, 1e-6);
  EXPECT_VEC2_NEAR(r.line.front(), Vec2(53, 40), 1e-9);
  EXPECT_VEC2_NEAR(r.line.back(), Vec2(0, 118), 1e-9);
  EXPECT_EQ(toDialogue(r).substr(0, 60), "Drive on R1 3.0 m and turn right 90 degrees at I1 onto R2.\nD");
}

// A centre X at the origin; the stem road W → X arrives from the west heading east; branches
// leave X at the given headings (degrees).
Map junction(IntersectionKind kind, const std::vector<double>& headings_deg) {
  MapData m;
  m.name = "junction";
  m.surfaces = {{"concrete", {Vec3(178, 176, 168), Vec3(10, 10, 10)}}, {"grass", {Vec3(70, 120, 50), Vec3(10, 10, 10)}}};
  m.intersections = {{"X", kind, Vec2(0, 0), std::nullopt}, {"W", IntersectionKind::End, Vec2(-20, 0), std::nullopt}};
  auto road = [&](const std::string& id, const std::string& from, const std::string& to, Vec2 a, Vec2 b) {
    Road r;
    r.id = id;
    r.from = from;
    r.to = to;
    r.centerline = Polyline2({a, b});
    r.width = 2;
    r.surface = "concrete";
    r.left = r.right = "grass";
    m.roads.push_back(r);
  };
  road("S", "W", "X", Vec2(-20, 0), Vec2(0, 0));
  for (std::size_t i = 0; i < headings_deg.size(); ++i) {
    const std::string id = "B" + std::to_string(i);
    const Vec2 end = 20 * unitVector(degToRad(headings_deg[i]));
    m.intersections.push_back({"E" + id, IntersectionKind::End, end, std::nullopt});
    road(id, "X", "E" + id, Vec2(0, 0), end);
  }
  return Map(m);
}

double turnAngleDeg(RoadGraph& graph, const std::string& from_road, const std::string& from_end, const std::string& to_road,
                    const std::string& to_end) {
  const RouteResult r = graph.route(at(from_road + "@" + from_end + "+5"), at(to_road + "@" + to_end + "+5"));
  EXPECT_TRUE(r.route) << r.reason;
  if (!r.route) return 0;
  EXPECT_EQ(r.route->legs.size(), 3u);
  return radToDeg(r.route->legs.at(1).angle);
}

TEST(TurnAngles, AtACrossLeftIsPlusNinetyStraightZeroRightMinusNinety) {
  const Map map = junction(IntersectionKind::Cross, {90, 0, -90});
  RoadGraph graph(map);
  EXPECT_NEAR(turnAngleDeg(graph, "S", "W", "B0", "EB0"), 90, 1e-9);
  EXPECT_NEAR(turnAngleDeg(graph, "S", "W", "B1", "EB1"), 0, 1e-9);
  EXPECT_NEAR(turnAngleDeg(graph, "S", "W", "B2", "EB2"), -90, 1e-9);
}

TEST(TurnAngles, AtATTheStemTurnsNinetyEitherWay) {
  const Map map = junction(IntersectionKind::T, {90, -90});
  RoadGraph graph(map);
  EXPECT_NEAR(turnAngleDeg(graph, "S", "W", "B0", "EB0"), 90, 1e-9);
  EXPECT_NEAR(turnAngleDeg(graph, "S", "W", "B1", "EB1"), -90, 1e-9);
  // Along the top of the T: arriving southward on B0 and going on south is straight.
  EXPECT_NEAR(turnAngleDeg(graph, "B0", "EB0", "B1", "EB1"), 0, 1e-9);
}

TEST(TurnAngles, AtASymmetricYEveryTurnIsSixtyDegrees) {
  const Map map = junction(IntersectionKind::Y, {60, -60});  // three roads 120° apart
  RoadGraph graph(map);
  EXPECT_NEAR(turnAngleDeg(graph, "S", "W", "B0", "EB0"), 60, 1e-9);
  EXPECT_NEAR(turnAngleDeg(graph, "S", "W", "B1", "EB1"), -60, 1e-9);
  EXPECT_NEAR(turnAngleDeg(graph, "B0", "EB0", "B1", "EB1"), 60, 1e-9);
  EXPECT_NEAR(turnAngleDeg(graph, "B0", "EB0", "S", "W"), -60, 1e-9);
}

TEST(TurnAngles, BetweenTheBranchesOfANarrowYTheTurnIsOneHundredTwentyDegrees) {
  const Map map = junction(IntersectionKind::Y, {30, -30});  // branches 60° apart
  RoadGraph graph(map);
  EXPECT_NEAR(turnAngleDeg(graph, "S", "W", "B0", "EB0"), 30, 1e-9);
  EXPECT_NEAR(turnAngleDeg(graph, "B0", "EB0", "B1", "EB1"), 120, 1e-9);
  EXPECT_NEAR(turnAngleDeg(graph, "B1", "EB1", "B0", "EB0"), -120, 1e-9);
}

Map gridMap(int n) {
  GridMapOptions o;
  o.columns = o.rows = n;
  return Map(makeGridMap(o));
}

TEST(SameRoad, StartAndGoalOnOneRoadInBothDirections) {
  const Map map = gridMap(3);
  RoadGraph graph(map);
  for (const auto& [from, to] : {std::pair{"H0_0@I0_0+5", "H0_0@I0_0+32"}, std::pair{"H0_0@I0_0+32", "H0_0@I0_0+5"}}) {
    const RouteResult r = graph.route(at(from), at(to));
    ASSERT_TRUE(r.route) << r.reason;
    EXPECT_EQ(describe(*r.route), std::vector<std::string>{"drive H0_0 27.0"}) << from;
    EXPECT_NEAR(r.route->length_m, 27, 1e-9);
  }
}

TEST(SameRoad, AOneWayRoadCannotBeDrivenBackwards) {
  MapData data = makeGridMap(GridMapOptions{2, 2, 40, 2});
  for (Road& r : data.roads) r.oneway = true;  // H: east, V: north: no way back west or south
  const Map map(data);
  RoadGraph graph(map);
  EXPECT_TRUE(graph.route(at("H0_0@I0_0+5"), at("H0_0@I0_0+30")).route);
  const RouteResult back = graph.route(at("H0_0@I0_0+30"), at("H0_0@I0_0+5"));
  EXPECT_FALSE(back.route);
  EXPECT_NE(back.reason.find("one-way"), std::string::npos) << back.reason;
  RouteOptions dijkstra;
  dijkstra.use_astar = false;
  EXPECT_FALSE(graph.route(at("H0_0@I0_0+30"), at("H0_0@I0_0+5"), dijkstra).route);
}

TEST(Blocked, ABlockedIntersectionForcesTheDetourAroundIt) {
  const Map map = gridMap(3);  // 40 m spacing
  RoadGraph graph(map);
  const RouteResult direct = graph.route(at("H0_0@I0_0+10"), at("H1_0@I2_0+10"));
  ASSERT_TRUE(direct.route);
  EXPECT_NEAR(direct.route->length_m, 30 + 30, 1e-9);
  RouteOptions options;
  options.blocked = {"I1_0"};
  const RouteResult detour = graph.route(at("H0_0@I0_0+10"), at("H1_0@I2_0+10"), options);
  ASSERT_TRUE(detour.route) << detour.reason;
  // Back 10 m to I0_0, up 40, across 80, down 40, and 10 m to the goal.
  EXPECT_NEAR(detour.route->length_m, 10 + 40 + 80 + 40 + 10, 1e-9);
  for (const std::string& x : detour.route->intersections) EXPECT_NE(x, "I1_0");
}

TEST(Blocked, BlockingARoadUsesTheNextBestAndBlockingAllSaysWhy) {
  const Map map = gridMap(2);  // a square of four roads
  RoadGraph graph(map);
  RouteOptions options;
  options.blocked = {"H0_0"};
  const RouteResult around = graph.route(at("V0_0@I0_0+5"), at("V1_0@I1_0+5"), options);
  ASSERT_TRUE(around.route) << around.reason;
  EXPECT_EQ(around.route->roads, (std::vector<std::string>{"V0_0", "H0_1", "V1_0"}));
  options.blocked = {"H0_0", "H0_1"};
  const RouteResult none = graph.route(at("V0_0@I0_0+5"), at("V1_0@I1_0+5"), options);
  EXPECT_FALSE(none.route);
  EXPECT_NE(none.reason.find("blocked"), std::string::npos) << none.reason;
  options.blocked = {"V1_0"};
  EXPECT_EQ(graph.route(at("V0_0@I0_0+5"), at("V1_0@I1_0+5"), options).reason, "the goal road V1_0 is blocked");
  options.blocked = {"R404"};
  EXPECT_THROW(graph.route(at("V0_0@I0_0+5"), at("V1_0@I1_0+5"), options), NotFound);
}

TEST(Unreachable, RoadsInDifferentPiecesOfTheNetworkHaveNoRoute) {
  MapData data = makeGridMap(GridMapOptions{2, 2, 40, 2});
  data.intersections.push_back({"P", IntersectionKind::End, Vec2(200, 0), std::nullopt});
  data.intersections.push_back({"Q", IntersectionKind::End, Vec2(240, 0), std::nullopt});
  Road island = data.roads.front();
  island.id = "Island";
  island.from = "P";
  island.to = "Q";
  island.centerline = Polyline2({Vec2(200, 0), Vec2(240, 0)});
  data.roads.push_back(island);
  const Map map(data);
  RoadGraph graph(map);
  const RouteResult r = graph.route(at("H0_0@I0_0+5"), at("Island@P+5"));
  EXPECT_FALSE(r.route);
  EXPECT_NE(r.reason.find("different parts of the network"), std::string::npos) << r.reason;
}

TEST(Search, AStarAndDijkstraFindRoutesOfTheSameCostOnRandomPairs) {
  MapData data = makeGridMap(GridMapOptions{12, 12, 30, 2});
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> factor(1.0, 2.0);
  for (Road& r : data.roads) r.cost_factor = factor(rng);  // make costs differ from lengths
  const Map map(data);
  RoadGraph graph(map);
  std::uniform_int_distribution<std::size_t> pick(0, map.roads().size() - 1);
  std::uniform_real_distribution<double> along(0.0, 30.0);
  RouteOptions dijkstra;
  dijkstra.use_astar = false;
  for (int i = 0; i < 100; ++i) {
    const Road& a = map.roads()[pick(rng)];
    const Road& b = map.roads()[pick(rng)];
    const RoadPosition from{a.id, a.from, along(rng)}, to{b.id, b.to, along(rng)};
    const RouteResult fast = graph.route(from, to), reference = graph.route(from, to, dijkstra);
    ASSERT_TRUE(fast.route && reference.route);
    EXPECT_NEAR(fast.route->cost, reference.route->cost, 1e-9) << toString(from) << " -> " << toString(to);
  }
}

TEST(Search, TiesAreBrokenTheSameWayEveryTime) {
  // Across a grid, many routes have exactly the same length and turns.
  const Map map = gridMap(6);
  RoadGraph graph(map);
  const RouteResult first = graph.route(at("H0_0@I0_0+5"), at("H4_5@I5_5+5"));
  ASSERT_TRUE(first.route);
  for (int i = 0; i < 5; ++i) {
    RoadGraph again(map);
    EXPECT_EQ(describe(*again.route(at("H0_0@I0_0+5"), at("H4_5@I5_5+5")).route), describe(*first.route));
  }
}

TEST(RouteOptions, DefaultsAreValid) {
  EXPECT_NO_THROW(RouteOptions{}.validate());
  RouteOptions o;
  o.turn_penalty_m_per_90deg = -1;
  EXPECT_THROW(o.validate(), InvalidInput);
}

}  // namespace
}  // namespace mapnav
