#include "mapnav/geometry/polyline2.h"

#include <cmath>

#include <gtest/gtest.h>

#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

// (0,0) → (4,0) → (4,3): 4 m east, then 3 m north (a left turn).
Polyline2 lShape() { return Polyline2({Vec2(0, 0), Vec2(4, 0), Vec2(4, 3)}); }

TEST(Polyline2, ArcLengthOfLShape) {
  const Polyline2 l = lShape();
  EXPECT_EQ(l.size(), 3u);
  EXPECT_EQ(l.segmentCount(), 2u);
  EXPECT_DOUBLE_EQ(l.length(), 7.0);
  EXPECT_DOUBLE_EQ(l.arcLengthAt(0), 0.0);
  EXPECT_DOUBLE_EQ(l.arcLengthAt(1), 4.0);
  EXPECT_DOUBLE_EQ(l.arcLengthAt(2), 7.0);
  EXPECT_EQ(Polyline2().length(), 0.0);
  EXPECT_EQ(Polyline2({Vec2(1, 1)}).length(), 0.0);
}

TEST(Polyline2, PointAtClampsToTheEnds) {
  const Polyline2 l = lShape();
  EXPECT_VEC2_NEAR(l.pointAt(2), Vec2(2, 0), 1e-15);
  EXPECT_VEC2_NEAR(l.pointAt(4), Vec2(4, 0), 1e-15);
  EXPECT_VEC2_NEAR(l.pointAt(5.5), Vec2(4, 1.5), 1e-15);
  EXPECT_EQ(l.pointAt(-1), Vec2(0, 0));
  EXPECT_EQ(l.pointAt(7), Vec2(4, 3));
  EXPECT_EQ(l.pointAt(100), Vec2(4, 3));
}

TEST(Polyline2, TangentAndHeadingAt) {
  const Polyline2 l = lShape();
  EXPECT_VEC2_NEAR(l.tangentAt(2), Vec2(1, 0), 1e-15);
  EXPECT_VEC2_NEAR(l.tangentAt(4), Vec2(0, 1), 1e-15);  // at a vertex: the next segment
  EXPECT_VEC2_NEAR(l.tangentAt(3.999), Vec2(1, 0), 1e-15);
  EXPECT_VEC2_NEAR(l.tangentAt(7), Vec2(0, 1), 1e-15);  // at the end: the last segment
  EXPECT_VEC2_NEAR(l.tangentAt(-5), Vec2(1, 0), 1e-15);
  EXPECT_NEAR(l.headingAt(5), kPi / 2, 1e-15);
  EXPECT_NEAR(l.headingAt(1), 0.0, 1e-15);
  EXPECT_EQ(l.segmentIndexAt(0), 0u);
  EXPECT_EQ(l.segmentIndexAt(4), 1u);
  EXPECT_EQ(l.segmentIndexAt(7), 1u);
}

TEST(Polyline2, ZeroLengthSegmentsAreSkipped) {
  const Polyline2 d({Vec2(0, 0), Vec2(0, 0), Vec2(4, 0), Vec2(4, 0), Vec2(4, 3), Vec2(4, 3)});
  EXPECT_DOUBLE_EQ(d.length(), 7.0);
  EXPECT_EQ(d.segmentIndexAt(0), 1u);
  EXPECT_EQ(d.segmentIndexAt(4), 3u);
  EXPECT_EQ(d.segmentIndexAt(7), 3u);
  EXPECT_VEC2_NEAR(d.tangentAt(0), Vec2(1, 0), 1e-15);
  EXPECT_VEC2_NEAR(d.tangentAt(4), Vec2(0, 1), 1e-15);
  EXPECT_VEC2_NEAR(d.tangentAt(7), Vec2(0, 1), 1e-15);
  EXPECT_VEC2_NEAR(d.pointAt(5), Vec2(4, 1), 1e-15);
  const auto p = d.project(Vec2(6, -2));  // outer corner
  EXPECT_EQ(p.segment, 3u);
  EXPECT_DOUBLE_EQ(p.arc_length, 4.0);
  const auto q = d.project(Vec2(4.5, 3.5));  // beyond the end
  EXPECT_EQ(q.segment, 3u);
  EXPECT_DOUBLE_EQ(q.arc_length, 7.0);
  EXPECT_DOUBLE_EQ(q.lateral, -0.5);
}

TEST(Polyline2, ProjectOnBothSides) {
  const Polyline2 l = lShape();
  auto p = l.project(Vec2(2, 1));  // left of the eastward leg
  EXPECT_DOUBLE_EQ(p.arc_length, 2.0);
  EXPECT_DOUBLE_EQ(p.lateral, 1.0);
  EXPECT_DOUBLE_EQ(p.distance, 1.0);
  EXPECT_VEC2_NEAR(p.point, Vec2(2, 0), 1e-15);
  EXPECT_EQ(p.segment, 0u);

  p = l.project(Vec2(2, -1.5));  // right of it
  EXPECT_DOUBLE_EQ(p.arc_length, 2.0);
  EXPECT_DOUBLE_EQ(p.lateral, -1.5);
  EXPECT_DOUBLE_EQ(p.distance, 1.5);

  p = l.project(Vec2(5, 1));  // east of the northward leg: its right
  EXPECT_DOUBLE_EQ(p.arc_length, 5.0);
  EXPECT_DOUBLE_EQ(p.lateral, -1.0);
  EXPECT_VEC2_NEAR(p.point, Vec2(4, 1), 1e-15);
  EXPECT_EQ(p.segment, 1u);

  p = l.project(Vec2(3, 1.5));  // inside the corner: 1 from the north leg, 1.5 from the east leg
  EXPECT_DOUBLE_EQ(p.arc_length, 5.5);
  EXPECT_DOUBLE_EQ(p.lateral, 1.0);
  EXPECT_EQ(p.segment, 1u);

  p = l.project(Vec2(6, -2));  // outside the corner: the vertex is closest, on the right
  EXPECT_DOUBLE_EQ(p.arc_length, 4.0);
  EXPECT_VEC2_NEAR(p.point, Vec2(4, 0), 1e-15);
  EXPECT_NEAR(p.distance, std::sqrt(8.0), 1e-15);
  EXPECT_NEAR(p.lateral, -std::sqrt(8.0), 1e-15);
  EXPECT_EQ(p.segment, 1u);
}

TEST(Polyline2, ProjectNearAHairpinTipTakesTheSideOfTheTurn) {
  // East 10 m, then back west-north-west: a left-turning hairpin whose inside (between the legs) is
  // on the left. (10.5, 1) is closest to the tip; it is left of the first leg's line but outside
  // the hairpin, above the second leg: on the right.
  const Polyline2 hairpin({Vec2(0, 0), Vec2(10, 0), Vec2(0, 1)});
  const auto p = hairpin.project(Vec2(10.5, 1));
  EXPECT_EQ(p.point, Vec2(10, 0));
  EXPECT_DOUBLE_EQ(p.arc_length, 10.0);
  EXPECT_EQ(p.segment, 1u);
  EXPECT_DOUBLE_EQ(p.distance, std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(p.lateral, -std::sqrt(1.25));
  // Between the legs, just inside the tip: left.
  const auto q = hairpin.project(Vec2(9, 0.05));
  EXPECT_GT(q.lateral, 0.0);
  EXPECT_NEAR(std::abs(q.lateral), q.distance, 1e-15);
}

TEST(Polyline2, ProjectBeyondTheEnds) {
  const Polyline2 l = lShape();
  auto p = l.project(Vec2(-3, 2));  // before the start, left of the first leg's line
  EXPECT_EQ(p.arc_length, 0.0);
  EXPECT_EQ(p.point, Vec2(0, 0));
  EXPECT_DOUBLE_EQ(p.distance, std::sqrt(13.0));
  EXPECT_DOUBLE_EQ(p.lateral, 2.0);
  EXPECT_EQ(p.segment, 0u);

  p = l.project(Vec2(5, 7));  // beyond the end, right of the last leg's line
  EXPECT_DOUBLE_EQ(p.arc_length, 7.0);
  EXPECT_EQ(p.point, Vec2(4, 3));
  EXPECT_DOUBLE_EQ(p.distance, std::sqrt(17.0));
  EXPECT_DOUBLE_EQ(p.lateral, -1.0);
  EXPECT_EQ(p.segment, 1u);

  p = l.project(Vec2(2.5, 3.5));  // beyond the end on the left
  EXPECT_DOUBLE_EQ(p.arc_length, 7.0);
  EXPECT_DOUBLE_EQ(p.lateral, 1.5);
  EXPECT_DOUBLE_EQ(p.distance, std::sqrt(1.5 * 1.5 + 0.25));
}

TEST(Polyline2, ProjectTiesTakeTheSmallestArcLength) {
  // A U: (0,0) → (10,0) → (10,2) → (0,2). (5,1) is 1 from both long legs.
  const Polyline2 u({Vec2(0, 0), Vec2(10, 0), Vec2(10, 2), Vec2(0, 2)});
  const auto p = u.project(Vec2(5, 1));
  EXPECT_DOUBLE_EQ(p.arc_length, 5.0);
  EXPECT_EQ(p.point, Vec2(5, 0));
  EXPECT_DOUBLE_EQ(p.lateral, 1.0);
  EXPECT_EQ(p.segment, 0u);
  // Slightly nearer the return leg: that one wins.
  const auto q = u.project(Vec2(5, 1.25));
  EXPECT_DOUBLE_EQ(q.arc_length, 17.0);
  EXPECT_DOUBLE_EQ(q.lateral, 0.75);
  EXPECT_EQ(q.segment, 2u);
}

TEST(Polyline2, ProjectOnDegeneratePolylines) {
  const auto p = Polyline2({Vec2(1, 1)}).project(Vec2(4, 5));
  EXPECT_EQ(p.point, Vec2(1, 1));
  EXPECT_DOUBLE_EQ(p.distance, 5.0);
  EXPECT_EQ(p.arc_length, 0.0);
  const auto q = Polyline2({Vec2(1, 1), Vec2(1, 1)}).project(Vec2(4, 5));
  EXPECT_EQ(q.point, Vec2(1, 1));
  EXPECT_DOUBLE_EQ(q.distance, 5.0);
  EXPECT_EQ(Polyline2().pointAt(3), Vec2::Zero());
  EXPECT_EQ(Polyline2({Vec2(2, 3)}).pointAt(3), Vec2(2, 3));
}

TEST(Polyline2, OffsetOfLShapeIsMitred) {
  const Polyline2 left = lShape().offset(1.0);
  ASSERT_EQ(left.size(), 3u);
  // The lines y = 1 and x = 3 meet at the inner corner (3, 1).
  EXPECT_VEC2_NEAR(left.points()[0], Vec2(0, 1), 1e-15);
  EXPECT_VEC2_NEAR(left.points()[1], Vec2(3, 1), 1e-15);
  EXPECT_VEC2_NEAR(left.points()[2], Vec2(3, 3), 1e-15);
  EXPECT_NEAR(left.length(), 5.0, 1e-14);

  const Polyline2 right = lShape().offset(-1.0);
  ASSERT_EQ(right.size(), 3u);
  // y = -1 and x = 5 meet at the outer corner (5, -1).
  EXPECT_VEC2_NEAR(right.points()[0], Vec2(0, -1), 1e-15);
  EXPECT_VEC2_NEAR(right.points()[1], Vec2(5, -1), 1e-15);
  EXPECT_VEC2_NEAR(right.points()[2], Vec2(5, 3), 1e-15);
  EXPECT_NEAR(right.length(), 9.0, 1e-14);

  // A 60° turn to the right, offset 2 to the left (the outside): the miter is d / cos(60° / 2) long.
  const Polyline2 bend({Vec2(0, 0), Vec2(10, 0), Vec2(10 + std::cos(degToRad(60)), -std::sin(degToRad(60)))});
  const Vec2 corner = bend.offset(2.0).points()[1];
  EXPECT_NEAR((corner - Vec2(10, 0)).norm(), 2.0 / std::cos(degToRad(30)), 1e-12);
  EXPECT_NEAR(corner.y(), 2.0, 1e-12);  // on the first leg's offset line
}

TEST(Polyline2, OffsetMiterIsCappedAtFourTimesTheDistance) {
  // A hairpin: east 10 m, then back west-north-west. The miter would be ~20 m long.
  const Polyline2 hairpin({Vec2(0, 0), Vec2(10, 0), Vec2(0, 1)});
  for (double d : {1.0, -0.5}) {
    const Vec2 v(10, 0);
    const Vec2 corner = hairpin.offset(d).points()[1];
    EXPECT_NEAR((corner - v).norm(), 4 * std::abs(d), 1e-12) << d;
    // Along the bisector of the two left normals, on the side of d.
    const Vec2 n = (leftNormal(Vec2(1, 0)) + leftNormal((Vec2(0, 1) - v).normalized())).normalized();
    EXPECT_VEC2_NEAR((corner - v) / d, 4 * n, 1e-12) << d;
  }
  // Zero-length segments keep their place.
  const Polyline2 dup({Vec2(0, 0), Vec2(4, 0), Vec2(4, 0), Vec2(4, 3)});
  const Polyline2 off = dup.offset(1.0);
  ASSERT_EQ(off.size(), 4u);
  EXPECT_VEC2_NEAR(off.points()[1], Vec2(3, 1), 1e-15);
  EXPECT_VEC2_NEAR(off.points()[2], Vec2(3, 1), 1e-15);
}

TEST(Polyline2, ReversedSliceBounds) {
  const Polyline2 l = lShape();
  const Polyline2 r = l.reversed();
  EXPECT_EQ(r.points(), (std::vector<Vec2>{Vec2(4, 3), Vec2(4, 0), Vec2(0, 0)}));
  EXPECT_DOUBLE_EQ(r.length(), 7.0);
  EXPECT_DOUBLE_EQ(r.arcLengthAt(1), 3.0);

  const Polyline2 s = l.slice(1, 6);
  ASSERT_EQ(s.size(), 3u);
  EXPECT_VEC2_NEAR(s.points()[0], Vec2(1, 0), 1e-15);
  EXPECT_VEC2_NEAR(s.points()[1], Vec2(4, 0), 1e-15);
  EXPECT_VEC2_NEAR(s.points()[2], Vec2(4, 2), 1e-15);
  EXPECT_DOUBLE_EQ(s.length(), 5.0);
  const Polyline2 within = l.slice(-3, 2.5);  // clamped, inside one segment
  EXPECT_EQ(within.points(), (std::vector<Vec2>{Vec2(0, 0), Vec2(2.5, 0)}));
  EXPECT_DOUBLE_EQ(l.slice(0, 100).length(), 7.0);

  const Box2 b = l.bounds();
  EXPECT_EQ(b.min(), Vec2(0, 0));
  EXPECT_EQ(b.max(), Vec2(4, 3));
  EXPECT_TRUE(Polyline2().bounds().isEmpty());
}

}  // namespace
}  // namespace mapnav
