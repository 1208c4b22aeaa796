#pragma once
#include <optional>
#include <vector>

#include "mapnav/geometry/types.h"

namespace mapnav {

/// A directed line segment from a to b.
struct Segment2 {
  Vec2 a = Vec2::Zero();
  Vec2 b = Vec2::Zero();

  Vec2 vector() const { return b - a; }
  double length() const { return (b - a).norm(); }
  /// Unit direction a→b; (1, 0) for a degenerate segment.
  Vec2 direction() const;
  /// Heading of a→b, radians counter-clockwise from +x.
  double heading() const;
  /// a + t (b - a).
  Vec2 pointAt(double t) const { return a + t * (b - a); }
  /// The parameter t in [0, 1] of the point of the segment closest to p.
  double closestParameter(const Vec2& p) const;
  Vec2 closestPoint(const Vec2& p) const { return pointAt(closestParameter(p)); }
  double distanceTo(const Vec2& p) const { return (closestPoint(p) - p).norm(); }
  /// Signed distance of p from the infinite line, positive on the left of a→b.
  double signedDistance(const Vec2& p) const;
  Segment2 reversed() const { return {b, a}; }
  Box2 bounds() const;
};

/// Do the closed segments share a point? Exact (CGAL exact predicates), so touching at an end point
/// or being collinear and overlapping counts.
bool segmentsIntersect(const Segment2& s, const Segment2& t);

/// The intersection point of two segments that cross at a single point; nothing when they do not
/// meet or overlap along a piece (then there is no single point).
std::optional<Vec2> segmentIntersection(const Segment2& s, const Segment2& t);

/// The total-least-squares line through `points` (at least one): it passes through their mean,
/// written to `mean`, along the returned unit direction of their largest spread, oriented with x ≥ 0.
Vec2 principalDirection(const std::vector<Vec2>& points, Vec2& mean);

/// Smallest angle between the two segments' lines, in [0, pi/2].
double angleBetweenLines(const Segment2& s, const Segment2& t);

}  // namespace mapnav
