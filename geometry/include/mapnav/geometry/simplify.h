#pragma once
#include <vector>

#include "mapnav/geometry/types.h"

namespace mapnav {

/// Polyline simplification with CGAL's Polyline_simplification_2 (Douglas–Peucker-style stop at a
/// squared-distance cost): removes vertices while every removed vertex stays within `tolerance`
/// metres of the simplified line. End points are kept. Used to turn curves into the few straight
/// interest segments the papers match against. Consecutive repeated points are merged; where the
/// polyline crosses or touches itself, the meeting point becomes a vertex that is never removed.
std::vector<Vec2> simplifyPolyline(const std::vector<Vec2>& points, double tolerance);

/// The same answer as simplifyPolyline, point for point, fast for a chain of pixel centres (a
/// contour traced in an image: integer coordinates, each step to one of the 8 neighbours, no point
/// repeated except a ring's closing point, no two diagonal steps crossing). It runs CGAL's greedy
/// loop — the same priority queue, cost and order — without the triangulation, testing a removal
/// against the remaining vertices in a grid instead. Any other input goes to simplifyPolyline.
std::vector<Vec2> simplifyPixelChain(const std::vector<Vec2>& points, double tolerance);

/// simplifyPixelChain at several tolerances at once, answer k at tolerances[k] (in any order). The
/// greedy loop removes the same vertices in the same order at every tolerance until the smallest
/// one's stop, so each larger tolerance goes on from where the smaller stopped: the cost of the
/// largest alone.
std::vector<std::vector<Vec2>> simplifyPixelChainAt(const std::vector<Vec2>& points,
                                                    const std::vector<double>& tolerances);

}  // namespace mapnav
