#include "mapnav/map/map.h"

#include <gtest/gtest.h>

#include "map_fixtures.h"
#include "mapnav/core/error.h"
#include "mapnav/geometry/polygon.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

class CrossOfFourRoads : public ::testing::Test {
 protected:
  Map map{testing::crossOfFourRoads()};
};

TEST_F(CrossOfFourRoads, LooksUpByIdAndThrowsNotFoundForUnknownIds) {
  EXPECT_EQ(map.road("R2").to, "N");
  EXPECT_EQ(map.intersection("W").kind, IntersectionKind::End);
  EXPECT_EQ(map.findRoad("R9"), nullptr);
  EXPECT_THROW(map.road("R9"), NotFound);
  EXPECT_THROW(map.intersection("I9"), NotFound);
  ASSERT_NE(map.findSurface("grass"), nullptr);
  EXPECT_EQ(map.findSurface("grass")->rgb, Vec3(70, 120, 50));
}

TEST_F(CrossOfFourRoads, RoadEndsAreSortedByHeadingLeavingTheIntersection) {
  const auto ends = map.roadsAt("I1");
  ASSERT_EQ(ends.size(), 4u);
  // Headings out of I1: S −90°, E 0°, N 90°, W 180°.
  EXPECT_EQ(ends[0].road->id, "R4");
  EXPECT_EQ(ends[1].road->id, "R1");
  EXPECT_EQ(ends[2].road->id, "R2");
  EXPECT_EQ(ends[3].road->id, "R3");
  EXPECT_NEAR(ends[0].heading_out, -kPi / 2, 1e-12);
  EXPECT_NEAR(ends[3].heading_out, kPi, 1e-12);
  EXPECT_TRUE(ends[0].at_from);
  // At the dead end E the road arrives heading east, so it leaves heading west.
  const auto at_e = map.roadsAt("E");
  ASSERT_EQ(at_e.size(), 1u);
  EXPECT_FALSE(at_e[0].at_from);
  EXPECT_NEAR(std::abs(at_e[0].heading_out), kPi, 1e-12);
}

TEST_F(CrossOfFourRoads, NeighboursAreTheFourEndsInIdOrder) {
  const auto n = map.neighbours("I1");
  ASSERT_EQ(n.size(), 4u);
  EXPECT_EQ(n[0]->id, "E");
  EXPECT_EQ(n[1]->id, "N");
  EXPECT_EQ(n[2]->id, "S");
  EXPECT_EQ(n[3]->id, "W");
}

TEST_F(CrossOfFourRoads, EdgesAreOffsetHalfAWidthToEachSide) {
  const Road& east = map.road("R1");
  EXPECT_VEC2_NEAR(map.leftEdge(east).front(), Vec2(0, 1), 1e-12);
  EXPECT_VEC2_NEAR(map.leftEdge(east).back(), Vec2(20, 1), 1e-12);
  EXPECT_VEC2_NEAR(map.rightEdge(east).back(), Vec2(20, -1), 1e-12);
  EXPECT_NEAR(std::abs(signedArea(map.roadPolygon(east))), 40.0, 1e-9);
}

TEST_F(CrossOfFourRoads, DerivedCrossShapeIsTheSquareWhereTheRoadsOverlap) {
  // Edge points one half-width (1 m) into each road: the hull is the 2 m × 2 m square at the centre.
  const Polygon2& shape = map.intersectionShape(map.intersection("I1"));
  EXPECT_NEAR(signedArea(shape), 4.0, 1e-9);  // counter-clockwise
  for (const Vec2& corner : {Vec2(1, 1), Vec2(-1, 1), Vec2(-1, -1), Vec2(1, -1)}) {
    EXPECT_TRUE(std::any_of(shape.begin(), shape.end(), [&](const Vec2& p) { return (p - corner).norm() < 1e-9; }))
        << "corner " << corner.transpose();
  }
}

TEST_F(CrossOfFourRoads, RoadsNearFindsPavedAreaWithinTheRadiusNearestFirst) {
  // (10, 3) is 2 m from R1's paved area (its edge is at y = 1).
  EXPECT_TRUE(map.roadsNear(Vec2(10, 3), 1.5).empty());
  const auto near = map.roadsNear(Vec2(10, 3), 2.5);
  ASSERT_EQ(near.size(), 1u);
  EXPECT_EQ(near[0]->id, "R1");
  // R2's area is 9 m away; R3's and R4's nearest point is the centre, sqrt(109) − 1 = 9.44 m away.
  const auto both = map.roadsNear(Vec2(10, 3), 9.2);
  ASSERT_EQ(both.size(), 2u);
  EXPECT_EQ(both[0]->id, "R1");
  EXPECT_EQ(both[1]->id, "R2");
  EXPECT_EQ(map.roadsNear(Vec2(10, 3), 9.5).size(), 4u);
}

TEST_F(CrossOfFourRoads, PolygonQueriesFindWhatMeetsThePolygon) {
  const Polygon2 box{{9.5, -0.5}, {10.5, -0.5}, {10.5, 0.5}, {9.5, 0.5}};
  const auto roads = map.roadsMeeting(box);
  ASSERT_EQ(roads.size(), 1u);
  EXPECT_EQ(roads[0]->id, "R1");
  EXPECT_TRUE(map.intersectionsMeeting(box).empty());
  // A square beside R1, 1.5 m off its centre line: meets the 1 m half-width? No. 0.8 m off: yes.
  EXPECT_TRUE(map.roadsMeeting({{9, 1.5}, {11, 1.5}, {11, 3}, {9, 3}}).empty());
  EXPECT_EQ(map.roadsMeeting({{9, 0.8}, {11, 0.8}, {11, 3}, {9, 3}}).size(), 1u);
  const auto centre = map.intersectionsMeeting({{-0.2, -0.2}, {0.2, -0.2}, {0.2, 0.2}, {-0.2, 0.2}});
  ASSERT_EQ(centre.size(), 1u);
  EXPECT_EQ(centre[0]->id, "I1");
}

TEST(Map, LandmarksInAPolygonAndTheRoadTheyStandBeside) {
  MapData data = testing::crossOfFourRoads();
  data.landmarks = {Landmark{"T1", LandmarkKind::Tree, Vec2(10, 2.5), 0.15, 6, "", {}},     // 1.5 m off R1's paving
                    Landmark{"T2", LandmarkKind::Tree, Vec2(-3, 4), 0.15, 6, "", {}},      // 2 m off R2, 2 m off R3
                    Landmark{"P1", LandmarkKind::Pole, Vec2(10, -2), 0.1, 5, "R3", {}},    // names R3, 9 m off it
                    Landmark{"M1", LandmarkKind::Manhole, Vec2(0.2, -15), 0.3, 0, "", {}}};  // in R4's paving
  const Map map(data);
  const auto in = map.landmarksIn({{5, -5}, {15, -5}, {15, 5}, {5, 5}});
  ASSERT_EQ(in.size(), 2u);
  EXPECT_EQ(in[0]->id, "T1");
  EXPECT_EQ(in[1]->id, "P1");
  EXPECT_TRUE(map.landmarksIn({{5, 3}, {15, 3}, {15, 5}, {5, 5}}).empty());
  EXPECT_EQ(map.roadBeside(map.landmarks()[0])->id, "R1");
  EXPECT_EQ(map.roadBeside(map.landmarks()[1])->id, "R2");  // a tie at 2 m: the first id
  EXPECT_EQ(map.roadBeside(map.landmarks()[2])->id, "R3");  // the road it names, though R1 is nearer
  EXPECT_EQ(map.roadBeside(map.landmarks()[3])->id, "R4");
  EXPECT_TRUE(map.warnings().empty());  // within 10 m of their roads, nothing standing on the paving
}

TEST_F(CrossOfFourRoads, BoundsCoverThePavedArea) {
  EXPECT_VEC2_NEAR(map.bounds().min(), Vec2(-21, -21), 1e-9);
  EXPECT_VEC2_NEAR(map.bounds().max(), Vec2(21, 21), 1e-9);
  ASSERT_EQ(map.components().size(), 1u);
  EXPECT_EQ(map.components()[0].size(), 5u);
}

TEST(Map, ComponentsListTheFirstIntersectionsPieceFirst) {
  MapData data = testing::crossOfFourRoads();
  data.intersections.push_back({"Z", IntersectionKind::Other, Vec2(100, 100), std::nullopt});
  const Map map(data);
  ASSERT_EQ(map.components().size(), 2u);
  EXPECT_EQ(map.components()[0].front(), 0u);
  EXPECT_EQ(map.components()[1], std::vector<std::size_t>{5});
}

TEST(Map, RefusesInvalidDataWithEveryIssue) {
  MapData data = testing::crossOfFourRoads();
  data.roads[0].to = "nowhere";
  data.roads[1].width = -1;
  try {
    Map map(data, "built.json");
    FAIL() << "expected ValidationError";
  } catch (const ValidationError& e) {
    EXPECT_EQ(e.file(), "built.json");
    ASSERT_EQ(countSeverity(e.issues(), Severity::Error), 2u);
    EXPECT_EQ(e.issues()[0].where, "/roads/0/to");
    EXPECT_EQ(e.issues()[1].where, "/roads/1/width");
  }
}

TEST(IntersectionKind, NamesRoundTrip) {
  for (IntersectionKind kind : allIntersectionKinds()) EXPECT_EQ(intersectionKindFromString(toString(kind)), kind);
  EXPECT_EQ(toString(IntersectionKind::Y), "Y");
  EXPECT_FALSE(intersectionKindFromString("cross "));
}

}  // namespace
}  // namespace mapnav
