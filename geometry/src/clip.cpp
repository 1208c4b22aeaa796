#include "mapnav/geometry/clip.h"

#include <algorithm>
#include <cmath>

#include <CGAL/Boolean_set_operations_2.h>
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Polygon_2.h>
#include <CGAL/Polygon_with_holes_2.h>

#include "mapnav/geometry/polygon.h"

namespace mapnav {

namespace {

using EK = CGAL::Exact_predicates_exact_constructions_kernel;
using ExactPolygon = CGAL::Polygon_2<EK>;
using ExactPolygonWithHoles = CGAL::Polygon_with_holes_2<EK>;

ExactPolygon toExact(const Polygon2& ring) {
  ExactPolygon p;
  for (const Vec2& v : ring) p.push_back(EK::Point_2(v.x(), v.y()));
  if (p.is_clockwise_oriented()) p.reverse_orientation();
  return p;
}

Polygon2 fromExact(const ExactPolygon& p) {
  Polygon2 ring;
  for (auto it = p.vertices_begin(); it != p.vertices_end(); ++it) {
    ring.emplace_back(CGAL::to_double(it->x()), CGAL::to_double(it->y()));
  }
  return ring;
}

void intersectSimple(const Polygon2& a, const Polygon2& b, std::vector<Polygon2>& out) {
  std::vector<ExactPolygonWithHoles> pieces;
  CGAL::intersection(toExact(a), toExact(b), std::back_inserter(pieces));
  for (const auto& piece : pieces) out.push_back(counterClockwise(fromExact(piece.outer_boundary())));
}

bool allFinite(const Polygon2& ring) {
  return std::all_of(ring.begin(), ring.end(), [](const Vec2& p) { return p.allFinite(); });
}

}  // namespace

std::vector<Polygon2> intersectPolygons(const Polygon2& a, const Polygon2& b) {
  std::vector<Polygon2> out;
  if (allFinite(a) && allFinite(b) && isSimple(a) && isSimple(b)) intersectSimple(a, b, out);
  return out;
}

namespace {

// Parameters along s where it meets the ring's edges, with 0 and 1, sorted and unique.
std::vector<double> breakpoints(const Segment2& s, const Polygon2& ring, std::vector<double> ts) {
  const double len2 = (s.b - s.a).squaredNorm();
  if (len2 == 0) return ts;
  auto param = [&](const Vec2& p) { return std::clamp((p - s.a).dot(s.b - s.a) / len2, 0.0, 1.0); };
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Segment2 edge{ring[i], ring[(i + 1) % ring.size()]};
    if (!segmentsIntersect(s, edge)) continue;
    if (const auto p = segmentIntersection(s, edge)) {
      ts.push_back(param(*p));
    } else {  // collinear overlap: its ends are where s enters and leaves the edge
      ts.push_back(param(edge.a));
      ts.push_back(param(edge.b));
    }
  }
  return ts;
}

std::vector<double> sortedUnique(std::vector<double> ts) {
  ts.push_back(0.0);
  ts.push_back(1.0);
  std::sort(ts.begin(), ts.end());
  ts.erase(std::unique(ts.begin(), ts.end(), [](double x, double y) { return y - x < 1e-12; }), ts.end());
  return ts;
}

void appendMerged(std::vector<Interval>& out, double t0, double t1) {
  if (!out.empty() && t0 - out.back().second < 1e-12) {
    out.back().second = t1;
  } else {
    out.emplace_back(t0, t1);
  }
}

}  // namespace

std::vector<Interval> intervalsInside(const Segment2& s, const Polygon2& ring) {
  std::vector<Interval> out;
  if (ring.size() < 3) return out;
  const auto ts = sortedUnique(breakpoints(s, ring, {}));
  for (std::size_t i = 0; i + 1 < ts.size(); ++i) {
    if (contains(ring, s.pointAt((ts[i] + ts[i + 1]) / 2))) appendMerged(out, ts[i], ts[i + 1]);
  }
  return out;
}

std::vector<Interval> intervalsOutside(const Segment2& s, const std::vector<const Polygon2*>& rings) {
  std::vector<double> ts;
  for (const Polygon2* ring : rings) ts = breakpoints(s, *ring, std::move(ts));
  ts = sortedUnique(std::move(ts));
  std::vector<Interval> out;
  constexpr double kOnBoundary = 1e-7;  // metres: a point this close to an outline is on it
  for (std::size_t i = 0; i + 1 < ts.size(); ++i) {
    const Vec2 mid = s.pointAt((ts[i] + ts[i + 1]) / 2);
    const bool covered = std::any_of(rings.begin(), rings.end(), [&](const Polygon2* ring) {
      return ring->size() >= 3 && contains(*ring, mid) && boundaryDistance(*ring, mid) > kOnBoundary;
    });
    if (!covered) appendMerged(out, ts[i], ts[i + 1]);
  }
  return out;
}

}  // namespace mapnav
