#pragma once
// Internal to geometry/: the CGAL kernel and conversions every CGAL-using file shares.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>

#include "mapnav/geometry/types.h"

namespace mapnav::cgal {

/// Exact predicates (orientation, intersection tests are never wrong), inexact constructions.
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_2;
using Segment = K::Segment_2;

inline Point toCgal(const Vec2& p) { return {p.x(), p.y()}; }
inline Vec2 fromCgal(const Point& p) { return {CGAL::to_double(p.x()), CGAL::to_double(p.y())}; }

}  // namespace mapnav::cgal
