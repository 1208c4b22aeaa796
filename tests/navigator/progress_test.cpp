#include "mapnav/navigator/progress.h"

#include <gtest/gtest.h>

#include "mapnav/core/error.h"
#include "mapnav/testing/maps.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

class CampusDialogueRoute : public ::testing::Test {
 protected:
  const Map& map = testing::campusMap();
  RoadGraph graph{map};
  Route route = *graph.route(parseRoadPosition("R1@I1+3"), parseRoadPosition("R3@I3+2")).route;
};

TEST_F(CampusDialogueRoute, ProjectingAPoseNearR1GivesItsRoadPosition) {
  // 3 m east of I1 (50, 40) on R1 (which runs east), 0.5 m north of it, heading 170 degrees.
  const auto p = projectToRoad(map, Pose2(53, 40.5, degToRad(170)));
  ASSERT_TRUE(p);
  EXPECT_EQ(p->position.road, "R1");
  EXPECT_EQ(p->position.node, "I1");
  EXPECT_NEAR(p->position.meters, 3.0, 1e-9);
  EXPECT_NEAR(p->position.lateral, 0.5, 1e-9);
  EXPECT_NEAR(p->distance, 0.5, 1e-9);
  EXPECT_NEAR(radToDeg(p->heading_error), 170, 1e-9);
  EXPECT_FALSE(projectToRoad(map, Pose2(75, 60, 0)));  // in the middle of a lawn, 20 m from every road
}

TEST_F(CampusDialogueRoute, ProgressMovesThroughTheLegsToTheGoal) {
  RouteProgress progress(route);
  const double length = route.line.length();
  double last_to_go = length;
  std::vector<std::size_t> legs;
  for (double s = 0; s <= length; s += 0.5) {
    const Vec2 p = route.line.pointAt(s);
    const ProgressStatus st = progress.update(Pose2(p, route.line.headingAt(s)));
    EXPECT_NEAR(st.along_m, s, 1e-6);
    EXPECT_LE(st.to_go_m, last_to_go + 1e-9);
    EXPECT_FALSE(st.off_route);
    last_to_go = st.to_go_m;
    if (legs.empty() || legs.back() != st.leg) legs.push_back(st.leg);
  }
  // Drive legs are 0, 2, 4, 6, 8 (turns between them).
  EXPECT_EQ(legs, (std::vector<std::size_t>{0, 2, 4, 6, 8}));
  EXPECT_TRUE(progress.update(Pose2(route.line.back(), 0)).finished);
}

TEST_F(CampusDialogueRoute, OffTheRouteOrABlockedRoadAheadCallsForANewRoute) {
  RouteProgress progress(route);
  ProgressStatus st = progress.update(Pose2(50, 60, kPi / 2));  // on R2, halfway to I2
  EXPECT_EQ(route.legs[st.leg].road, "R2");
  EXPECT_FALSE(needsReplan(st, route, {}));
  EXPECT_TRUE(needsReplan(st, route, {"R5"}));   // ahead
  EXPECT_TRUE(needsReplan(st, route, {"I4"}));   // an intersection ahead
  EXPECT_FALSE(needsReplan(st, route, {"R1"}));  // behind
  st = progress.update(Pose2(54, 62, kPi / 2));  // 4 m east of R2
  EXPECT_TRUE(st.off_route);
  EXPECT_NEAR(st.off_route_m, 4.0, 1e-6);
  EXPECT_TRUE(needsReplan(st, route, {}));
}

TEST_F(CampusDialogueRoute, ReplanningFromWhereTheVehicleIsAvoidsTheBlockedRoad) {
  RouteOptions options;
  options.blocked = {"R5"};
  const RouteResult again = replan(graph, Pose2(50, 60, kPi / 2), route.to, options);
  ASSERT_TRUE(again.route) << again.reason;
  for (const std::string& road : again.route->roads) EXPECT_NE(road, "R5");
  EXPECT_EQ(again.route->roads.back(), "R3");
  EXPECT_FALSE(replan(graph, Pose2(75, 60, 0), route.to).route);
}

TEST(ProgressOptions, DefaultsAreValid) {
  EXPECT_NO_THROW(ProgressOptions{}.validate());
  ProgressOptions o;
  o.off_route_tolerance_m = 0;
  EXPECT_THROW(o.validate(), InvalidInput);
}

// Out and back: east along R1 from x = 60 to the via point at x = 75, back west to I1 (50, 40), right
// onto R2 to (50, 50), as the mission's planThrough joins it: the line comes back over itself.
Route outAndBack() {
  Route r;
  r.legs = {Leg{LegAction::Drive, "R1", 15.0, "", 0}, Leg{LegAction::Turn, "R1", 0, "R1@I1+25", kPi},
            Leg{LegAction::Drive, "R1", 25.0, "", 0}, Leg{LegAction::Turn, "R2", 0, "I1", -kPi / 2},
            Leg{LegAction::Drive, "R2", 10.0, "", 0}};
  r.line = Polyline2({Vec2(60, 40), Vec2(75, 40), Vec2(50, 40), Vec2(50, 50)});
  r.length_m = 50;
  return r;
}

TEST(RouteProgressOutAndBack, TheTwoPassesOfTheRoadAreFollowedInOrder) {
  const Route route = outAndBack();
  EXPECT_EQ(turnaroundArcs(route), std::vector<double>{15.0});
  RouteProgress progress(route);
  // On the way out, 2 m before the via point, the way back (2 m past it, the same spot) is in the
  // 15 m search window and as near: progress stays on the way out.
  for (const double x : {60.0, 65.0, 70.0, 73.0}) {
    const ProgressStatus st = progress.update(Pose2(x, 40, 0));
    EXPECT_NEAR(st.along_m, x - 60, 1e-9) << x;
    EXPECT_EQ(st.leg, 0u) << x;
    EXPECT_DOUBLE_EQ(st.stretch_begin_m, 0.0);
    EXPECT_DOUBLE_EQ(st.stretch_end_m, 15.0);
  }
  // 0.2 m before it (within turnaround_reach_m, 0.25 m): reached, onto the way back (leg 2).
  ProgressStatus st = progress.update(Pose2(74.8, 40, 0));
  EXPECT_DOUBLE_EQ(st.along_m, 15.0);
  EXPECT_EQ(st.leg, 2u);
  EXPECT_DOUBLE_EQ(st.stretch_begin_m, 15.0);
  EXPECT_DOUBLE_EQ(st.stretch_end_m, 50.0);
  // Turning there, then driving back west: never back onto the way out.
  st = progress.update(Pose2(74.8, 40, kPi / 2));
  EXPECT_NEAR(st.along_m, 15.2, 1e-9);
  for (const double x : {73.0, 65.0, 55.0}) {
    st = progress.update(Pose2(x, 40, kPi));
    EXPECT_NEAR(st.along_m, 75 - x + 15, 1e-9) << x;
    EXPECT_EQ(st.leg, 2u) << x;
  }
  st = progress.update(Pose2(50, 45, kPi / 2));
  EXPECT_NEAR(st.along_m, 45.0, 1e-9);
  EXPECT_EQ(st.leg, 4u);
}

// The legs' metres come from road positions, the line from centre-line slices: they may differ by a
// hair, and a plan ending a hair past the fold would end going back (random campus seed 4 stood
// 0.6 m before its via point: the follower took the reversed last heading for "past the end").
// The turnaround is the fold's own arc length.
TEST(RouteProgressOutAndBack, TheTurnaroundIsWhereTheLineFolds) {
  Route route = outAndBack();
  route.legs[0].meters = 15.0000004;
  EXPECT_EQ(turnaroundArcs(route), std::vector<double>{15.0});
  route.legs[0].meters = 13.5;  // no fold within 1 m: the legs' figure
  EXPECT_EQ(turnaroundArcs(route), std::vector<double>{13.5});
}

TEST(RouteProgressOutAndBack, BeforeTheFirstPoseOnlyTheWayOutIsSearched) {
  RouteProgress progress(outAndBack());
  // x = 70 is 10 m out and 20 m along on the way back; the first pose takes the way out.
  EXPECT_NEAR(progress.update(Pose2(70, 40, 0)).along_m, 10.0, 1e-9);
}

}  // namespace
}  // namespace mapnav
