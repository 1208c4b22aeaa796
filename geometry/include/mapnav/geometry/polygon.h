#pragma once
// Polygon predicates that must be robust (CGAL's exact-predicates kernel inside) and a few plain
// measures. Polygons are Polygon2 rings: first vertex not repeated.
#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

#include "mapnav/geometry/types.h"

namespace mapnav {

/// Positive for counter-clockwise rings (shoelace).
double signedArea(const Polygon2& ring);
Vec2 centroid(const Polygon2& ring);
/// Exact: no two non-adjacent edges meet and adjacent edges meet only at their shared vertex.
/// Rings with fewer than 3 vertices are not simple.
bool isSimple(const Polygon2& ring);
/// Exact point-in-polygon for a simple ring; points on the boundary count as inside.
bool contains(const Polygon2& ring, const Vec2& p);
/// How many of `points` contains(ring, p) holds for, with the ring converted once (for many points).
std::size_t countContained(const Polygon2& ring, const std::vector<Vec2>& points);
/// Distance from p to the ring's boundary.
double boundaryDistance(const Polygon2& ring, const Vec2& p);
/// Counter-clockwise convex hull (CGAL), no collinear points.
Polygon2 convexHull(const std::vector<Vec2>& points);
/// The ring made counter-clockwise.
Polygon2 counterClockwise(Polygon2 ring);

/// A pair of segments that meet: indices of their first vertices and a point where they meet.
struct SegmentHit {
  std::size_t i = 0;
  std::size_t j = 0;
  Vec2 point = Vec2::Zero();
};

/// Segments of the chain `points` (closed: also the last-to-first edge) that meet other than at the
/// vertex adjacent segments share. O((n + k) log n) with a sweep over bounding boxes; exact tests.
std::vector<SegmentHit> selfIntersections(const std::vector<Vec2>& points, bool closed);

/// Pairs (segment i of a, segment j of b) that meet, with a meeting point. Same method.
std::vector<SegmentHit> chainIntersections(const std::vector<Vec2>& a, const std::vector<Vec2>& b);

}  // namespace mapnav
