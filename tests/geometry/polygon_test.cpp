#include "mapnav/geometry/polygon.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>
#include <set>
#include <utility>

#include <gtest/gtest.h>

#include "mapnav/geometry/segment2.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

const Polygon2 kSquare{Vec2(0, 0), Vec2(2, 0), Vec2(2, 2), Vec2(0, 2)};  // counter-clockwise
// An L: [0,2]x[0,1] plus [0,1]x[1,2], counter-clockwise.
const Polygon2 kEll{Vec2(0, 0), Vec2(2, 0), Vec2(2, 1), Vec2(1, 1), Vec2(1, 2), Vec2(0, 2)};
const Polygon2 kBowTie{Vec2(0, 0), Vec2(2, 2), Vec2(2, 0), Vec2(0, 2)};

std::set<std::pair<std::size_t, std::size_t>> pairsOf(const std::vector<SegmentHit>& hits) {
  std::set<std::pair<std::size_t, std::size_t>> out;
  for (const SegmentHit& h : hits) out.insert({h.i, h.j});
  return out;
}

TEST(Polygon, SignedAreaAndCentroid) {
  EXPECT_DOUBLE_EQ(signedArea(kSquare), 4.0);
  const Polygon2 cw(kSquare.rbegin(), kSquare.rend());
  EXPECT_DOUBLE_EQ(signedArea(cw), -4.0);
  EXPECT_DOUBLE_EQ(signedArea(kEll), 3.0);
  EXPECT_EQ(signedArea({Vec2(0, 0), Vec2(1, 1)}), 0.0);
  EXPECT_VEC2_NEAR(centroid(kSquare), Vec2(1, 1), 1e-15);
  EXPECT_VEC2_NEAR(centroid(cw), Vec2(1, 1), 1e-15);
  EXPECT_VEC2_NEAR(centroid({Vec2(0, 0), Vec2(3, 0), Vec2(0, 3)}), Vec2(1, 1), 1e-15);
  // (2 · (1, 0.5) + 1 · (0.5, 1.5)) / 3
  EXPECT_VEC2_NEAR(centroid(kEll), Vec2(5.0 / 6.0, 5.0 / 6.0), 1e-15);
  // Far from the origin the result stays accurate.
  Polygon2 far = kSquare;
  for (Vec2& v : far) v += Vec2(1e6, -2e6);
  EXPECT_VEC2_NEAR(centroid(far), Vec2(1e6 + 1, -2e6 + 1), 1e-9);
  EXPECT_DOUBLE_EQ(signedArea(far), 4.0);
}

TEST(Polygon, IsSimple) {
  EXPECT_TRUE(isSimple(kSquare));
  EXPECT_TRUE(isSimple(kEll));
  EXPECT_TRUE(isSimple({Vec2(0, 0), Vec2(1, 0), Vec2(0, 1)}));
  EXPECT_TRUE(isSimple({Vec2(0, 0), Vec2(1, 0), Vec2(2, 0), Vec2(2, 2), Vec2(0, 2)}));  // collinear vertex
  EXPECT_FALSE(isSimple(kBowTie));
  EXPECT_FALSE(isSimple({Vec2(0, 0), Vec2(2, 0)}));                                 // too few
  EXPECT_FALSE(isSimple({Vec2(0, 0), Vec2(2, 0), Vec2(1, 0)}));                     // flat triangle
  EXPECT_FALSE(isSimple({Vec2(0, 0), Vec2(2, 0), Vec2(2, 0), Vec2(2, 2)}));         // repeated vertex
  EXPECT_FALSE(isSimple({Vec2(0, 0), Vec2(2, 0), Vec2(2, 2), Vec2(0, 2), Vec2(0, 0)}));  // first repeated
  EXPECT_FALSE(isSimple({Vec2(0, 0), Vec2(3, 0), Vec2(1, 0), Vec2(1, 2)}));         // spike back along an edge
  // A vertex touching a non-adjacent edge: (2, 0) lies on the edge (0,0)-(4,0).
  EXPECT_FALSE(isSimple({Vec2(0, 0), Vec2(4, 0), Vec2(4, 4), Vec2(2, 0), Vec2(0, 4)}));
}

TEST(Polygon, ContainsCountsTheBoundaryAsInside) {
  EXPECT_TRUE(contains(kSquare, Vec2(1, 1)));
  EXPECT_TRUE(contains(kSquare, Vec2(2, 1)));  // on an edge
  EXPECT_TRUE(contains(kSquare, Vec2(0, 0)));  // a vertex
  EXPECT_FALSE(contains(kSquare, Vec2(3, 1)));
  EXPECT_FALSE(contains(kSquare, Vec2(1, -1e-300)));
  EXPECT_TRUE(contains(Polygon2(kSquare.rbegin(), kSquare.rend()), Vec2(1, 1)));  // clockwise too
  EXPECT_TRUE(contains(kEll, Vec2(0.5, 1.5)));
  EXPECT_FALSE(contains(kEll, Vec2(1.5, 1.5)));  // the notch
  EXPECT_TRUE(contains(kEll, Vec2(1.5, 1)));     // the notch's edge
  EXPECT_FALSE(contains({}, Vec2(0, 0)));
}

// countContained agrees with contains() point by point: the L's inside, notch, edges and vertices,
// and the degenerate rings.
TEST(Polygon, CountContainedAgreesWithContains) {
  std::vector<Vec2> points;
  for (int i = -2; i <= 10; ++i)
    for (int j = -2; j <= 10; ++j) points.emplace_back(0.25 * i, 0.25 * j);
  for (const Polygon2& ring : {kSquare, kEll, Polygon2{}, Polygon2{Vec2(1, 1)}, Polygon2{Vec2(0, 0), Vec2(2, 2)}}) {
    std::size_t expected = 0;
    for (const Vec2& p : points) expected += contains(ring, p);
    EXPECT_EQ(countContained(ring, points), expected) << ring.size() << " vertices";
  }
  // The 2 x 2 square holds the 9 x 9 lattice points of [0, 2]² at 0.25 spacing.
  EXPECT_EQ(countContained(kSquare, points), 81u);
}

// Many points (counted by rows): random simple rings — star-shaped ones with vertices on whole
// numbers or anywhere, and staircases whose edges lie along the lattice's rows and columns — against
// contains() point by point, over a whole-number lattice (points on edges and vertices) and random
// points; also points that are NaN or infinite.
TEST(Polygon, CountContainedByRowsAgreesWithContainsOnRandomRings) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Polygon2> rings;
  for (int k = 0; k < 40; ++k) {
    const int n = 3 + static_cast<int>(unit(rng) * 40);
    std::vector<double> angles(n);
    for (double& a : angles) a = unit(rng) * 2 * std::numbers::pi;
    std::sort(angles.begin(), angles.end());
    Polygon2 ring;
    for (const double a : angles) {
      const double r = 3 + unit(rng) * 12;
      Vec2 v(20 + r * std::cos(a), 20 + r * std::sin(a));
      if (k % 2 == 0) v = v.array().round();
      if (ring.empty() || v != ring.back()) ring.push_back(v);
    }
    if (ring.size() >= 3 && isSimple(ring)) rings.push_back(ring);
  }
  for (int k = 0; k < 10; ++k) {  // a staircase: right and up in whole steps, then back along the axes
    Polygon2 ring{Vec2(5, 5)};
    Vec2 at(5, 5);
    for (int s = 0; s < 6; ++s) {
      at.x() += 1 + static_cast<int>(unit(rng) * 4);
      ring.push_back(at);
      at.y() += 1 + static_cast<int>(unit(rng) * 4);
      ring.push_back(at);
    }
    ring.push_back(Vec2(5, at.y()));
    rings.push_back(ring);
  }
  ASSERT_GT(rings.size(), 30u);
  std::vector<Vec2> points;
  for (int u = 0; u <= 40; ++u)
    for (int v = 0; v <= 40; ++v) points.emplace_back(u, v);
  for (int i = 0; i < 400; ++i) points.emplace_back(40 * unit(rng), 40 * unit(rng));
  for (int i = 0; i < 40; ++i) points.emplace_back(0.5 * static_cast<int>(80 * unit(rng)), 20);  // halves on one row
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  points.insert(points.end(), {Vec2(nan, 20), Vec2(20, nan), Vec2(inf, 20), Vec2(20, -inf)});
  std::size_t boundary = 0;
  for (const Polygon2& ring : rings) {
    std::vector<Vec2> mine = points;
    mine.insert(mine.end(), ring.begin(), ring.end());  // the vertices themselves
    for (std::size_t i = 0; i < ring.size(); ++i) mine.push_back(0.5 * (ring[i] + ring[(i + 1) % ring.size()]));
    std::size_t expected = 0;
    for (const Vec2& p : mine) {
      expected += contains(ring, p);
      boundary += boundaryDistance(ring, p) == 0;
    }
    EXPECT_EQ(countContained(ring, mine), expected) << ring.size() << " vertices";
  }
  EXPECT_GT(boundary, 1000u);  // many points lay on the boundary, where the exact test decides
}

TEST(Polygon, BoundaryDistance) {
  EXPECT_DOUBLE_EQ(boundaryDistance(kSquare, Vec2(1, 1)), 1.0);
  EXPECT_DOUBLE_EQ(boundaryDistance(kSquare, Vec2(1, 0.25)), 0.25);
  EXPECT_DOUBLE_EQ(boundaryDistance(kSquare, Vec2(3, 1)), 1.0);
  EXPECT_DOUBLE_EQ(boundaryDistance(kSquare, Vec2(3, 3)), std::sqrt(2.0));
  EXPECT_DOUBLE_EQ(boundaryDistance(kSquare, Vec2(-1, 1)), 1.0);  // the closing edge counts
  EXPECT_DOUBLE_EQ(boundaryDistance(kEll, Vec2(1.5, 1.75)), 0.5);
}

TEST(Polygon, ConvexHullOfKnownSet) {
  const std::vector<Vec2> points{Vec2(1, 1), Vec2(2, 2), Vec2(0, 0),   Vec2(1, 0),   Vec2(2, 0),
                                 Vec2(0, 2), Vec2(0.5, 1.5), Vec2(2, 1), Vec2(1.5, 0.2)};
  const Polygon2 hull = convexHull(points);
  ASSERT_EQ(hull.size(), 4u);  // (1, 0) and (2, 1) are on edges: dropped
  // Counter-clockwise from the lowest-left point.
  const auto start = std::find(hull.begin(), hull.end(), Vec2(0, 0));
  ASSERT_NE(start, hull.end());
  Polygon2 rotated(start, hull.end());
  rotated.insert(rotated.end(), hull.begin(), start);
  EXPECT_EQ(rotated, (Polygon2{Vec2(0, 0), Vec2(2, 0), Vec2(2, 2), Vec2(0, 2)}));
  EXPECT_DOUBLE_EQ(signedArea(hull), 4.0);
  EXPECT_TRUE(convexHull({}).empty());
  EXPECT_EQ(convexHull({Vec2(1, 1), Vec2(1, 1)}).size(), 1u);
}

TEST(Polygon, CounterClockwiseKeepsTheFirstVertex) {
  const Polygon2 cw{Vec2(0, 0), Vec2(0, 2), Vec2(2, 2), Vec2(2, 0)};
  EXPECT_EQ(counterClockwise(cw), kSquare);
  EXPECT_EQ(counterClockwise(kSquare), kSquare);
}

TEST(Polygon, SelfIntersectionsOfFigureEight) {
  // The bow-tie as a closed ring: only edges 0 ((0,0)-(2,2)) and 2 ((2,0)-(0,2)) cross, at (1, 1).
  auto hits = selfIntersections(kBowTie, true);
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_EQ(hits[0].i, 0u);
  EXPECT_EQ(hits[0].j, 2u);
  EXPECT_VEC2_NEAR(hits[0].point, Vec2(1, 1), 1e-15);

  // The same figure as an open chain back to its start: the last segment also meets the first at
  // (0, 0), which is not a shared vertex of adjacent segments there.
  Polygon2 chain = kBowTie;
  chain.push_back(kBowTie.front());
  hits = selfIntersections(chain, false);
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_EQ(hits[0].i, 0u);
  EXPECT_EQ(hits[0].j, 2u);
  EXPECT_VEC2_NEAR(hits[0].point, Vec2(1, 1), 1e-15);
  EXPECT_EQ(hits[1].i, 0u);
  EXPECT_EQ(hits[1].j, 3u);
  EXPECT_EQ(hits[1].point, Vec2(0, 0));
  // Closed, the repeated start makes a zero-length closing segment, which is skipped.
  EXPECT_EQ(pairsOf(selfIntersections(chain, true)), (std::set<std::pair<std::size_t, std::size_t>>{{0, 2}}));

  EXPECT_TRUE(selfIntersections(kSquare, true).empty());
  EXPECT_TRUE(selfIntersections(kEll, true).empty());
}

TEST(Polygon, SelfIntersectionsOfSpikeAndZeroLengthSegments) {
  // East to (2,0), straight back to (1,0), then north: segments 0 and 1 overlap (the nearer end of
  // the fold is (1,0)), and segment 2 starts on segment 0.
  const auto hits = selfIntersections({Vec2(0, 0), Vec2(2, 0), Vec2(1, 0), Vec2(1, 5)}, false);
  ASSERT_EQ(hits.size(), 2u);
  EXPECT_EQ(hits[0].i, 0u);
  EXPECT_EQ(hits[0].j, 1u);
  EXPECT_EQ(hits[0].point, Vec2(1, 0));
  EXPECT_EQ(hits[1].i, 0u);
  EXPECT_EQ(hits[1].j, 2u);
  EXPECT_EQ(hits[1].point, Vec2(1, 0));
  // A repeated point: segment 1 has no length; segments 0 and 2 still only share their vertex.
  EXPECT_TRUE(selfIntersections({Vec2(0, 0), Vec2(1, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1)}, false).empty());
  // Going straight on through a vertex is no fold.
  EXPECT_TRUE(selfIntersections({Vec2(0, 0), Vec2(1, 0), Vec2(2, 0)}, false).empty());
  EXPECT_TRUE(selfIntersections({}, true).empty());
  EXPECT_TRUE(selfIntersections({Vec2(1, 1)}, true).empty());
}

TEST(Polygon, SelfIntersectionsMatchBruteForceOnGridWalk) {
  // A random walk on the integer grid: plenty of exact touches, crossings and collinear overlaps.
  std::mt19937 rng(7);
  const Vec2 steps[8] = {Vec2(1, 0),  Vec2(1, 1),   Vec2(0, 1),  Vec2(-1, 1),
                         Vec2(-1, 0), Vec2(-1, -1), Vec2(0, -1), Vec2(1, -1)};
  std::uniform_int_distribution<int> pick(0, 7);
  std::vector<Vec2> walk{Vec2(0, 0)};
  std::vector<int> stepIndex;
  for (int k = 0; k < 400; ++k) {
    stepIndex.push_back(pick(rng));
    walk.push_back(walk.back() + steps[stepIndex.back()]);
  }
  std::set<std::pair<std::size_t, std::size_t>> expected;
  for (std::size_t i = 0; i + 1 < walk.size(); ++i) {
    for (std::size_t j = i + 1; j + 1 < walk.size(); ++j) {
      const bool hit = j == i + 1 ? stepIndex[j] == (stepIndex[i] + 4) % 8  // folds straight back
                                  : segmentsIntersect({walk[i], walk[i + 1]}, {walk[j], walk[j + 1]});
      if (hit) expected.insert({i, j});
    }
  }
  const auto hits = selfIntersections(walk, false);
  EXPECT_GT(expected.size(), 100u);
  EXPECT_EQ(pairsOf(hits), expected);
  EXPECT_EQ(hits.size(), expected.size());  // no duplicates
  for (const SegmentHit& h : hits) {
    // The reported point lies on both segments (exactly, on this grid).
    EXPECT_LT((Segment2{walk[h.i], walk[h.i + 1]}.distanceTo(h.point)), 1e-12);
    EXPECT_LT((Segment2{walk[h.j], walk[h.j + 1]}.distanceTo(h.point)), 1e-12);
  }
}

TEST(Polygon, SelfIntersectionsOfLongNorthboundChain) {
  // 100k segments all within x in [0, 1]: the sweep must not compare them all pairwise.
  std::vector<Vec2> zigzag;
  for (int k = 0; k <= 100000; ++k) zigzag.emplace_back(k % 2, 0.5 * k);
  EXPECT_TRUE(selfIntersections(zigzag, false).empty());
  // Closed round the right-hand side: (0, 50000) → (3, 50000) → (3, -1) → back to (0, 0). The new
  // edges touch the zig-zag only at the vertices they share with it.
  zigzag.push_back(Vec2(3, 50000));
  zigzag.push_back(Vec2(3, -1));
  EXPECT_TRUE(selfIntersections(zigzag, true).empty());
  // Ending at (0.5, 0.2) instead: edge 100001, (3, 50000) → (0.5, 0.2), reaches x = 1 only at
  // y = 10000.16, so it crosses each of the zig-zag's segments 0 ... 19999 once (segment k spans
  // y in [k/2, k/2 + 1/2] and all of x in [0, 1]). The closing edge to (0, 0) touches nothing else.
  zigzag.back() = Vec2(0.5, 0.2);
  const auto hits = selfIntersections(zigzag, true);
  ASSERT_EQ(hits.size(), 20000u);
  for (std::size_t k = 0; k < hits.size(); ++k) {
    ASSERT_EQ(hits[k].i, k);
    ASSERT_EQ(hits[k].j, 100001u);
  }
}

TEST(Polygon, ChainIntersectionsOfCrossingPolylines) {
  auto hits = chainIntersections({Vec2(0, 0), Vec2(4, 4)}, {Vec2(0, 4), Vec2(4, 0)});
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_EQ(hits[0].i, 0u);
  EXPECT_EQ(hits[0].j, 0u);
  EXPECT_VEC2_NEAR(hits[0].point, Vec2(2, 2), 1e-15);

  // A straight road and a zig-zag crossing it three times, at x = 1.5, 2.5 and 3.5.
  const std::vector<Vec2> road{Vec2(-1, 0), Vec2(0, 0), Vec2(10, 0)};
  const std::vector<Vec2> zig{Vec2(1, -1), Vec2(2, 1), Vec2(3, -1), Vec2(4, 1)};
  hits = chainIntersections(road, zig);
  ASSERT_EQ(hits.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(hits[k].i, 1u);
    EXPECT_EQ(hits[k].j, k);
    EXPECT_VEC2_NEAR(hits[k].point, Vec2(1.5 + static_cast<double>(k), 0), 1e-15);
  }
  // Swapped arguments swap the indices.
  const auto swapped = chainIntersections(zig, road);
  ASSERT_EQ(swapped.size(), 3u);
  EXPECT_EQ(swapped[2].i, 2u);
  EXPECT_EQ(swapped[2].j, 1u);
  // Touching at an end point counts; a chain's own crossings do not.
  hits = chainIntersections({Vec2(0, 0), Vec2(2, 0)}, {Vec2(2, 0), Vec2(3, 3)});
  ASSERT_EQ(hits.size(), 1u);
  EXPECT_EQ(hits[0].point, Vec2(2, 0));
  EXPECT_TRUE(chainIntersections(kBowTie, {Vec2(5, 5), Vec2(6, 6)}).empty());
  EXPECT_TRUE(chainIntersections({}, zig).empty());
}

}  // namespace
}  // namespace mapnav
