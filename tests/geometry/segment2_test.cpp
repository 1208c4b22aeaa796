#include "mapnav/geometry/segment2.h"

#include <cmath>

#include <gtest/gtest.h>

#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

TEST(Segment2, LengthDirectionHeading) {
  const Segment2 s{Vec2(1, 1), Vec2(4, 5)};
  EXPECT_DOUBLE_EQ(s.length(), 5.0);
  EXPECT_VEC2_NEAR(s.direction(), Vec2(0.6, 0.8), 1e-15);
  EXPECT_DOUBLE_EQ(s.heading(), std::atan2(4.0, 3.0));
  EXPECT_VEC2_NEAR(s.pointAt(0.5), Vec2(2.5, 3), 1e-15);
  EXPECT_NEAR((Segment2{Vec2(0, 0), Vec2(-1, 0)}.heading()), kPi, 1e-15);
  EXPECT_NEAR((Segment2{Vec2(0, 0), Vec2(0, -2)}.heading()), -kPi / 2, 1e-15);
  EXPECT_EQ(s.reversed().a, s.b);
  EXPECT_EQ(s.reversed().b, s.a);
}

TEST(Segment2, DegenerateSegmentHasDefaultDirection) {
  const Segment2 d{Vec2(2, 3), Vec2(2, 3)};
  EXPECT_EQ(d.direction(), Vec2(1, 0));
  EXPECT_EQ(d.heading(), 0.0);
  EXPECT_EQ(d.closestParameter(Vec2(10, 10)), 0.0);
  EXPECT_DOUBLE_EQ(d.distanceTo(Vec2(5, 7)), 5.0);
}

TEST(Segment2, ClosestParameterAndDistance) {
  const Segment2 s{Vec2(0, 0), Vec2(10, 0)};
  EXPECT_DOUBLE_EQ(s.closestParameter(Vec2(3, 5)), 0.3);
  EXPECT_EQ(s.closestParameter(Vec2(-2, 1)), 0.0);
  EXPECT_EQ(s.closestParameter(Vec2(12, -1)), 1.0);
  EXPECT_VEC2_NEAR(s.closestPoint(Vec2(3, 5)), Vec2(3, 0), 1e-15);
  EXPECT_DOUBLE_EQ(s.distanceTo(Vec2(3, 5)), 5.0);
  EXPECT_DOUBLE_EQ(s.distanceTo(Vec2(12, -1)), std::sqrt(5.0));
  EXPECT_DOUBLE_EQ(s.distanceTo(Vec2(-3, 4)), 5.0);
}

TEST(Segment2, SignedDistanceIsPositiveOnTheLeft) {
  const Segment2 s{Vec2(0, 0), Vec2(10, 0)};
  EXPECT_DOUBLE_EQ(s.signedDistance(Vec2(3, 5)), 5.0);
  EXPECT_DOUBLE_EQ(s.signedDistance(Vec2(3, -2)), -2.0);
  EXPECT_DOUBLE_EQ(s.signedDistance(Vec2(30, -2)), -2.0);  // the infinite line
  EXPECT_DOUBLE_EQ(s.reversed().signedDistance(Vec2(3, 5)), -5.0);
  const Segment2 diag{Vec2(0, 0), Vec2(1, 1)};
  EXPECT_NEAR(diag.signedDistance(Vec2(0, 2)), std::sqrt(2.0), 1e-15);
}

TEST(Segment2, Bounds) {
  const Box2 b = Segment2{Vec2(3, -1), Vec2(1, 2)}.bounds();
  EXPECT_EQ(b.min(), Vec2(1, -1));
  EXPECT_EQ(b.max(), Vec2(3, 2));
}

TEST(Segment2, IntersectPredicateCases) {
  const Segment2 s{Vec2(0, 0), Vec2(2, 0)};
  EXPECT_TRUE(segmentsIntersect({Vec2(0, 0), Vec2(2, 2)}, {Vec2(0, 2), Vec2(2, 0)}));  // crossing
  EXPECT_TRUE(segmentsIntersect(s, {Vec2(1, 0), Vec2(1, 1)}));                        // T-junction
  EXPECT_TRUE(segmentsIntersect(s, {Vec2(2, 0), Vec2(3, 1)}));                        // shared end point
  EXPECT_TRUE(segmentsIntersect(s, {Vec2(1, 0), Vec2(5, 0)}));                        // collinear overlap
  EXPECT_FALSE(segmentsIntersect(s, {Vec2(3, 0), Vec2(5, 0)}));                       // collinear, apart
  EXPECT_FALSE(segmentsIntersect(s, {Vec2(0, 1), Vec2(2, 1)}));                       // parallel
  EXPECT_FALSE(segmentsIntersect(s, {Vec2(1, 1e-300), Vec2(1, 1)}));                  // just above
  EXPECT_TRUE(segmentsIntersect(s, {Vec2(1, 0), Vec2(1, 0)}));                        // a point on s
  EXPECT_FALSE(segmentsIntersect(s, {Vec2(1, 1e-300), Vec2(1, 1e-300)}));
  // Decided exactly on the doubles: 0.1 and 0.3 are rounded so that (0.1, 0.3) lies 2.8e-17 below the
  // line y = 3x. A segment leaving that point to the lower right misses (0,0)-(1,3); one going left
  // along y = 0.3 crosses it.
  const Segment2 steep{Vec2(0, 0), Vec2(1, 3)};
  EXPECT_FALSE(segmentsIntersect(steep, {Vec2(0.1, 0.3), Vec2(1, 0)}));
  EXPECT_TRUE(segmentsIntersect(steep, {Vec2(0.1, 0.3), Vec2(-1, 0.3)}));
}

TEST(Segment2, IntersectionPoint) {
  const auto x = segmentIntersection({Vec2(0, 0), Vec2(2, 2)}, {Vec2(0, 2), Vec2(2, 0)});
  ASSERT_TRUE(x.has_value());
  EXPECT_VEC2_NEAR(*x, Vec2(1, 1), 1e-15);
  const auto y = segmentIntersection({Vec2(0, 0), Vec2(4, 0)}, {Vec2(1, -1), Vec2(2, 1)});
  ASSERT_TRUE(y.has_value());
  EXPECT_VEC2_NEAR(*y, Vec2(1.5, 0), 1e-15);
  // Collinear segments touching end to end meet at one point.
  const auto z = segmentIntersection({Vec2(0, 0), Vec2(1, 0)}, {Vec2(1, 0), Vec2(2, 0)});
  ASSERT_TRUE(z.has_value());
  EXPECT_EQ(*z, Vec2(1, 0));
  // Overlap along a piece, and no meeting: nothing.
  EXPECT_FALSE(segmentIntersection({Vec2(0, 0), Vec2(2, 0)}, {Vec2(1, 0), Vec2(3, 0)}).has_value());
  EXPECT_FALSE(segmentIntersection({Vec2(0, 0), Vec2(2, 0)}, {Vec2(0, 1), Vec2(2, 1)}).has_value());
  EXPECT_FALSE(segmentIntersection({Vec2(0, 0), Vec2(2, 0)}, {Vec2(3, -1), Vec2(3, 1)}).has_value());
}

TEST(Segment2, AngleBetweenLines) {
  const Segment2 x{Vec2(0, 0), Vec2(1, 0)};
  EXPECT_NEAR(angleBetweenLines(x, {Vec2(0, 0), Vec2(0, 3)}), kPi / 2, 1e-15);
  EXPECT_NEAR(angleBetweenLines(x, {Vec2(5, 5), Vec2(6, 6)}), kPi / 4, 1e-15);
  EXPECT_NEAR(angleBetweenLines(x, {Vec2(0, 0), Vec2(-1, 1)}), kPi / 4, 1e-15);  // 135° lines: 45°
  EXPECT_NEAR(angleBetweenLines(x, {Vec2(3, 1), Vec2(-2, 1)}), 0.0, 1e-15);      // anti-parallel
  EXPECT_NEAR(angleBetweenLines(x, {Vec2(0, 0), Vec2(std::sqrt(3.0), -1)}), kPi / 6, 1e-15);
}

}  // namespace
}  // namespace mapnav
