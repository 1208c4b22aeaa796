#include "mapnav/geometry/clip.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "mapnav/geometry/polygon.h"

namespace mapnav {
namespace {

// `actual` is `expected` up to where the ring starts: same vertex count, each vertex within `tol`
// once the rings are aligned at the vertex of `expected` nearest to actual[0], and counter-clockwise.
void expectSameRing(const Polygon2& actual, const Polygon2& expected, double tol, const std::string& what) {
  ASSERT_EQ(actual.size(), expected.size()) << what;
  ASSERT_FALSE(actual.empty()) << what;
  EXPECT_GT(signedArea(actual), 0) << what;
  std::size_t shift = 0;
  for (std::size_t i = 1; i < expected.size(); ++i) {
    if ((expected[i] - actual[0]).norm() < (expected[shift] - actual[0]).norm()) shift = i;
  }
  for (std::size_t i = 0; i < actual.size(); ++i) {
    const Vec2& e = expected[(i + shift) % expected.size()];
    EXPECT_LE((actual[i] - e).norm(), tol) << what << ": vertex " << i << " (" << actual[i].transpose()
                                           << ") against (" << e.transpose() << ")";
  }
}

// The pieces of `actual` are those of `expected` in any order: matched by nearest centroid, with the
// same area to `rel` and the same vertices to `tol`.
void expectSamePieces(const std::vector<Polygon2>& actual, const std::vector<Polygon2>& expected, double rel,
                      double tol, const std::string& what) {
  ASSERT_EQ(actual.size(), expected.size()) << what;
  std::vector<bool> taken(expected.size(), false);
  for (std::size_t i = 0; i < actual.size(); ++i) {
    std::size_t best = expected.size();
    for (std::size_t j = 0; j < expected.size(); ++j) {
      if (taken[j]) continue;
      if (best == expected.size() ||
          (centroid(expected[j]) - centroid(actual[i])).norm() < (centroid(expected[best]) - centroid(actual[i])).norm()) {
        best = j;
      }
    }
    taken[best] = true;
    const double area = signedArea(expected[best]);
    EXPECT_NEAR(signedArea(actual[i]), area, rel * std::abs(area)) << what << ": piece " << i;
    expectSameRing(actual[i], expected[best], tol, what + ", piece " + std::to_string(i));
  }
}

TEST(IntersectWithConvex, SquareAndTriangleMakeAPentagon) {
  // [0,1]^2 less what lies beyond x + y = 1.5: the corner (1,1) cut off, 1 - 0.5^2 / 2 = 0.875.
  const Polygon2 square{Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  const Polygon2 triangle{Vec2(0, 0), Vec2(1.5, 0), Vec2(0, 1.5)};
  const auto pieces = intersectWithConvex(square, triangle);
  ASSERT_EQ(pieces.size(), 1u);
  EXPECT_NEAR(signedArea(pieces[0]), 0.875, 1e-15);
  expectSameRing(pieces[0], {Vec2(0, 0), Vec2(1, 0), Vec2(1, 0.5), Vec2(0.5, 1), Vec2(0, 1)}, 1e-15, "pentagon");
}

TEST(IntersectWithConvex, ClockwiseInputGivesTheSameCounterClockwisePiece) {
  const Polygon2 square{Vec2(0, 1), Vec2(1, 1), Vec2(1, 0), Vec2(0, 0)};  // clockwise
  const Polygon2 triangle{Vec2(0, 1.5), Vec2(1.5, 0), Vec2(0, 0)};        // clockwise
  const auto pieces = intersectWithConvex(square, triangle);
  ASSERT_EQ(pieces.size(), 1u);
  expectSameRing(pieces[0], {Vec2(0, 0), Vec2(1, 0), Vec2(1, 0.5), Vec2(0.5, 1), Vec2(0, 1)}, 1e-15, "clockwise");
}

// A U: [0,3]x[0,1] with the arms [0,1]x[1,3] and [2,3]x[1,3], counter-clockwise.
const Polygon2 kU{Vec2(0, 0), Vec2(3, 0), Vec2(3, 3), Vec2(2, 3), Vec2(2, 1), Vec2(1, 1), Vec2(1, 3), Vec2(0, 3)};

TEST(IntersectWithConvex, ABandAcrossBothArmsOfAUGivesTwoPieces) {
  // y in [2, 4]: the two arms' tops, 1 x 1 each, not one ring joined along y = 2.
  const Polygon2 band{Vec2(-1, 2), Vec2(4, 2), Vec2(4, 4), Vec2(-1, 4)};
  expectSamePieces(intersectWithConvex(kU, band),
                   {{Vec2(0, 2), Vec2(1, 2), Vec2(1, 3), Vec2(0, 3)}, {Vec2(2, 2), Vec2(3, 2), Vec2(3, 3), Vec2(2, 3)}},
                   1e-15, 1e-15, "band");
}

TEST(IntersectWithConvex, AnEdgeOnTheClipLineFromOutsideBoundsNoPiece) {
  // y >= 1 meets the U's inner bottom edge (1,1)-(2,1), whose inside is below: two arms, no bridge.
  const Polygon2 upper{Vec2(-1, 1), Vec2(4, 1), Vec2(4, 5), Vec2(-1, 5)};
  expectSamePieces(intersectWithConvex(kU, upper),
                   {{Vec2(0, 1), Vec2(1, 1), Vec2(1, 3), Vec2(0, 3)}, {Vec2(2, 1), Vec2(3, 1), Vec2(3, 3), Vec2(2, 3)}},
                   1e-15, 1e-15, "upper");
  // y <= 1 keeps the U's base only, whose top edge is partly the clip line. The exact operations
  // keep the U's vertices (1,1) and (2,1) on it; the fast clip leaves them out (the same square).
  const Polygon2 lower{Vec2(-1, -1), Vec2(4, -1), Vec2(4, 1), Vec2(-1, 1)};
  expectSamePieces(intersectWithConvex(kU, lower), {{Vec2(0, 0), Vec2(3, 0), Vec2(3, 1), Vec2(0, 1)}}, 1e-15, 1e-15,
                   "lower");
  EXPECT_EQ(intersectPolygons(kU, lower).at(0).size(), 6u);
}

TEST(IntersectWithConvex, TouchingOnlyAtAVertexOrAnEdgeIsEmpty) {
  const Polygon2 square{Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  EXPECT_TRUE(intersectWithConvex(square, {Vec2(1, 1), Vec2(2, 1), Vec2(2, 2)}).empty());                 // a corner
  EXPECT_TRUE(intersectWithConvex(square, {Vec2(1, 0), Vec2(2, 0), Vec2(2, 1), Vec2(1, 1)}).empty());     // an edge
  EXPECT_TRUE(intersectWithConvex(square, {Vec2(5, 5), Vec2(6, 5), Vec2(6, 6)}).empty());                 // apart
  // A vertex of the subject on the clip outline, its edges outside: nothing either.
  EXPECT_TRUE(intersectWithConvex({Vec2(0, 0), Vec2(2, -1), Vec2(2, 1)}, {Vec2(-2, -2), Vec2(0, -2), Vec2(0, 2)}).empty());
}

TEST(IntersectWithConvex, AWholeSubjectInsideIsKeptAsItIs) {
  const Polygon2 square{Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  const auto pieces = intersectWithConvex(square, {Vec2(-1, -1), Vec2(4, -1), Vec2(-1, 4)});
  ASSERT_EQ(pieces.size(), 1u);
  EXPECT_EQ(pieces[0], square);
}

TEST(IntersectWithConvex, BadInputIsEmptyAndANonConvexClipIsTheExactIntersection) {
  const Polygon2 square{Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)};
  const Polygon2 bow_tie{Vec2(0, 0), Vec2(2, 2), Vec2(2, 0), Vec2(0, 2)};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(intersectWithConvex(bow_tie, square).empty());
  EXPECT_TRUE(intersectWithConvex(square, bow_tie).empty());
  EXPECT_TRUE(intersectWithConvex({Vec2(0, 0), Vec2(nan, 0), Vec2(0, 1)}, square).empty());
  EXPECT_TRUE(intersectWithConvex(square, {Vec2(0, 0), Vec2(1, 0)}).empty());
  EXPECT_TRUE(intersectWithConvex({}, square).empty());
  // Coordinates whose products overflow go to the exact operations: the square's lower half.
  const double big = 1e200;
  const Polygon2 huge{Vec2(0, 0), Vec2(big, 0), Vec2(big, big), Vec2(0, big)};
  const Polygon2 lower_half{Vec2(-big, -big), Vec2(2 * big, -big), Vec2(2 * big, big / 2), Vec2(-big, big / 2)};
  const auto halves = intersectWithConvex(huge, lower_half);
  ASSERT_EQ(halves.size(), 1u);
  Polygon2 corners = halves[0];
  std::sort(corners.begin(), corners.end(), [](const Vec2& a, const Vec2& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  EXPECT_EQ(corners, (Polygon2{Vec2(0, 0), Vec2(0, big / 2), Vec2(big, 0), Vec2(big, big / 2)}));
  // A non-convex clip (the U) goes to the exact operations: the square's two lower corners' parts.
  const Polygon2 wide{Vec2(-1, 1.5), Vec2(4, 1.5), Vec2(4, 2), Vec2(-1, 2)};
  expectSamePieces(intersectWithConvex(wide, kU), intersectPolygons(wide, kU), 1e-15, 0, "non-convex clip");
  EXPECT_EQ(intersectWithConvex(wide, kU).size(), 2u);
}

// A random simple polygon: star-shaped about `centre`, its radii varying by up to a factor of 10, so
// that it is mostly not convex and its spikes cross a clip polygon several times.
Polygon2 randomStar(std::mt19937& rng, const Vec2& centre, double size) {
  std::uniform_int_distribution<int> count(3, 24);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int n = count(rng);
  std::vector<double> angles;
  for (int i = 0; i < n; ++i) angles.push_back(2 * kPi * unit(rng));
  std::sort(angles.begin(), angles.end());
  Polygon2 ring;
  for (double a : angles) ring.push_back(centre + size * (0.1 + 0.9 * unit(rng)) * unitVector(a));
  return ring;
}

TEST(IntersectWithConvex, MatchesTheExactIntersectionOnRandomPolygons) {
  // Map-sized coordinates (hundreds of metres), polygons of metres to tens of metres.
  std::mt19937 rng(20261122);
  std::uniform_real_distribution<double> offset(-8.0, 8.0), size(2.0, 20.0), coin(0.0, 1.0);
  int compared = 0, split = 0;
  for (int trial = 0; trial < 6000; ++trial) {
    const Vec2 centre(300 + offset(rng), 200 + offset(rng));
    const double radius = size(rng);
    Polygon2 subject = randomStar(rng, centre, radius);
    if (coin(rng) < 0.5) std::reverse(subject.begin(), subject.end());  // clockwise half the time
    // The clip: the hull of 3 to 32 points in a square of up to the star's size, up to its radius
    // from its centre, where the spikes go in and out.
    const Vec2 middle = centre + radius * coin(rng) * unitVector(2 * kPi * coin(rng));
    const double spread = radius * (0.1 + 0.9 * coin(rng));
    std::vector<Vec2> cloud;
    const int points = 3 + static_cast<int>(coin(rng) * 30);
    for (int i = 0; i < points; ++i) cloud.push_back(middle + spread * Vec2(coin(rng) - 0.5, coin(rng) - 0.5));
    const Polygon2 clip = convexHull(cloud);
    if (clip.size() < 3 || !isSimple(subject)) continue;
    const auto fast = intersectWithConvex(subject, clip);
    const auto exact = intersectPolygons(subject, clip);
    const std::string what = "trial " + std::to_string(trial);
    expectSamePieces(fast, exact, 1e-9, 1e-9, what);
    if (::testing::Test::HasFailure()) return;  // one trial's messages are enough
    ++compared;
    split += exact.size() > 1 ? 1 : 0;
  }
  // The random cases include what matters: many compared, many cut into several pieces.
  EXPECT_GT(compared, 5500);
  EXPECT_GT(split, 300) << compared;
}

}  // namespace
}  // namespace mapnav
