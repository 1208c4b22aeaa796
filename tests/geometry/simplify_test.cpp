#include "mapnav/geometry/simplify.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "mapnav/geometry/segment2.h"
#include "mapnav/testing/support.h"

namespace mapnav {
namespace {

double distanceToPolyline(const std::vector<Vec2>& line, const Vec2& p) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i + 1 < line.size(); ++i) best = std::min(best, Segment2{line[i], line[i + 1]}.distanceTo(p));
  return best;
}

// Every vertex of `simplified` is a vertex of `original`, in the same order; returns the index in
// `original` of each.
std::vector<std::size_t> subsequenceIndices(const std::vector<Vec2>& original, const std::vector<Vec2>& simplified) {
  std::vector<std::size_t> at;
  std::size_t k = 0;
  for (const Vec2& v : simplified) {
    while (k < original.size() && original[k] != v) ++k;
    if (k == original.size()) return {};
    at.push_back(k++);
  }
  return at;
}

TEST(Simplify, StraightLineKeepsOnlyItsEnds) {
  std::vector<Vec2> line;
  for (int i = 0; i < 100; ++i) line.emplace_back(i, 2 * i);
  const auto s = simplifyPolyline(line, 0.01);
  EXPECT_EQ(s, (std::vector<Vec2>{Vec2(0, 0), Vec2(99, 198)}));
}

TEST(Simplify, DenseCircleArcStaysWithinTolerance) {
  // A quarter circle of radius 10 in 1000 vertices, tolerance 5 cm. A chord of angle phi deviates by
  // r (1 - cos(phi / 2)) from the arc, so each chord spans at most 2 acos(0.995) = 0.2 rad: at
  // least ceil((pi/2) / 0.2) = 8 chords, 9 vertices.
  const double r = 10, tol = 0.05;
  std::vector<Vec2> arc;
  for (int i = 0; i < 1000; ++i) {
    const double a = (kPi / 2) * i / 999.0;
    arc.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  const auto s = simplifyPolyline(arc, tol);
  EXPECT_GE(s.size(), 9u);
  EXPECT_LE(s.size(), 16u);
  EXPECT_EQ(s.front(), arc.front());
  EXPECT_EQ(s.back(), arc.back());
  const auto kept = subsequenceIndices(arc, s);
  ASSERT_EQ(kept.size(), s.size()) << "output is not a subsequence of the input";
  for (const Vec2& p : arc) EXPECT_LE(distanceToPolyline(s, p), tol + 1e-12);
  // A tighter tolerance keeps more vertices, and still honours it.
  const auto fine = simplifyPolyline(arc, 0.005);
  EXPECT_GT(fine.size(), s.size());
  // 2 acos(0.9995) = 0.0633 rad per chord: at least 25 chords (one fewer allowed for the sampling).
  EXPECT_GE(fine.size(), 25u);
  for (const Vec2& p : arc) EXPECT_LE(distanceToPolyline(fine, p), 0.005 + 1e-12);
}

TEST(Simplify, ZigZagBelowOrAboveTolerance) {
  // Teeth of height 0.1 along the x axis.
  std::vector<Vec2> zig;
  for (int i = 0; i <= 20; ++i) zig.emplace_back(i, (i % 2) * 0.1);
  EXPECT_EQ(simplifyPolyline(zig, 0.2), (std::vector<Vec2>{Vec2(0, 0), Vec2(20, 0)}));
  EXPECT_EQ(simplifyPolyline(zig, 0.04), zig);  // removing any vertex leaves it 0.1 from the new chord
  EXPECT_EQ(simplifyPolyline(zig, 0.0), zig);
}

TEST(Simplify, KeepsCornersOfAClosedSquare) {
  // The unit square's boundary sampled every 0.1, starting and ending at (0, 0).
  std::vector<Vec2> ring;
  const Vec2 corners[5] = {Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(0, 1), Vec2(0, 0)};
  for (int c = 0; c < 4; ++c) {
    for (int k = 0; k < 10; ++k) ring.push_back(corners[c] + (corners[c + 1] - corners[c]) * (k / 10.0));
  }
  ring.push_back(Vec2(0, 0));
  const auto s = simplifyPolyline(ring, 0.01);
  EXPECT_EQ(s, (std::vector<Vec2>(corners, corners + 5)));
}

TEST(Simplify, DegenerateInputs) {
  EXPECT_TRUE(simplifyPolyline({}, 1.0).empty());
  EXPECT_EQ(simplifyPolyline({Vec2(1, 2)}, 1.0), (std::vector<Vec2>{Vec2(1, 2)}));
  EXPECT_EQ(simplifyPolyline({Vec2(1, 2), Vec2(3, 4)}, 1.0), (std::vector<Vec2>{Vec2(1, 2), Vec2(3, 4)}));
  // Repeated points are merged.
  EXPECT_EQ(simplifyPolyline({Vec2(0, 0), Vec2(1, 0), Vec2(1, 0), Vec2(2, 0)}, 0.1),
            (std::vector<Vec2>{Vec2(0, 0), Vec2(2, 0)}));
  EXPECT_EQ(simplifyPolyline({Vec2(5, 5), Vec2(5, 5), Vec2(5, 5)}, 0.1), (std::vector<Vec2>{Vec2(5, 5)}));
  // A single bump higher than the tolerance survives.
  EXPECT_EQ(simplifyPolyline({Vec2(0, 0), Vec2(1, 0), Vec2(2, 1), Vec2(3, 0), Vec2(4, 0)}, 0.5),
            (std::vector<Vec2>{Vec2(0, 0), Vec2(2, 1), Vec2(4, 0)}));
}

}  // namespace
}  // namespace mapnav
