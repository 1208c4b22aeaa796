#pragma once
// Clipping shapes to a region: what part of a road lies inside the camera's view footprint.
#include <utility>
#include <vector>

#include "mapnav/geometry/segment2.h"
#include "mapnav/geometry/types.h"

namespace mapnav {

/// The intersection of two simple polygons with CGAL's Boolean set operations (exact kernel), as
/// the counter-clockwise outer rings of its pieces (holes are dropped: a clipped road has none).
/// Empty when either polygon is not simple or not finite (the Boolean operations require simple
/// input; split such a shape into simple pieces first).
std::vector<Polygon2> intersectPolygons(const Polygon2& a, const Polygon2& b);

/// The same intersection, same contract, for a clip polygon that is usually convex (a camera's view
/// footprint): when `clip` is strictly convex (every turn the same way, one turn round), it is cut
/// away one edge's half-plane at a time in doubles (Sutherland–Hodgman, with each cut splitting the
/// subject into its separate pieces rather than joining them by zero-width bridges); a vertex or an
/// edge that only touches the clip outline gives no piece, as with the exact operations. Otherwise,
/// or should rounding leave the crossings inconsistent, it is intersectPolygons. The pieces and
/// their vertices are intersectPolygons' up to rounding (within 3e-13 m on the campus replay,
/// where edges cross at shallow angles; 1e-9 m in the tests), except that a subject's vertex lying
/// exactly on the clip outline where a piece follows the outline is left out (a collinear vertex
/// the exact result keeps); the pieces' order and first vertices may differ.
std::vector<Polygon2> intersectWithConvex(const Polygon2& subject, const Polygon2& clip);

/// A piece of a segment: parameters t0 < t1 in [0, 1] along a → b.
using Interval = std::pair<double, double>;

/// The pieces of `s` inside the closed region `ring` (boundary included), in order along s.
std::vector<Interval> intervalsInside(const Segment2& s, const Polygon2& ring);

/// The pieces of `s` that are not strictly inside any of `rings` (points on a boundary are kept),
/// in order, merged where they touch.
std::vector<Interval> intervalsOutside(const Segment2& s, const std::vector<const Polygon2*>& rings);

}  // namespace mapnav
