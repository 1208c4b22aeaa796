#include "mapnav/geometry/polygon.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include <CGAL/Polygon_2_algorithms.h>
#include <CGAL/convex_hull_2.h>
#include <CGAL/intersections.h>

#include "mapnav/geometry/segment2.h"
#include "cgal_kernel.h"

namespace mapnav {

namespace {
using namespace cgal;
using CgalSegment = cgal::Segment;  // beside mapnav's own Segment2

// ---- bounding-box sweep ---------------------------------------------------------------------------

struct SweepSegment {
  double lo[2];  // box minimum (x, y)
  double hi[2];  // box maximum
  Vec2 a, b;
  std::size_t index;  // index of the segment's first vertex in its chain
  std::size_t rank;   // position among the chain's non-zero-length segments
  int chain;
};

void addChain(const std::vector<Vec2>& points, bool closed, int chain, std::vector<SweepSegment>& out) {
  const std::size_t n = points.size();
  if (n < 2) return;
  const std::size_t count = closed ? n : n - 1;
  std::size_t rank = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const Vec2& a = points[i];
    const Vec2& b = points[(i + 1) % n];
    if (a == b) continue;
    SweepSegment s;
    s.lo[0] = std::min(a.x(), b.x());
    s.lo[1] = std::min(a.y(), b.y());
    s.hi[0] = std::max(a.x(), b.x());
    s.hi[1] = std::max(a.y(), b.y());
    s.a = a;
    s.b = b;
    s.index = i;
    s.rank = rank++;
    s.chain = chain;
    out.push_back(s);
  }
}

// Sorts by the box minimum along the axis where the boxes overlap less, then calls
// visit(s, t) for every pair whose boxes overlap, until visit returns false.
template <class Visit>
void sweepPairs(std::vector<SweepSegment>& segments, Visit&& visit) {
  if (segments.size() < 2) return;
  // Pick the axis whose total box extent is smallest relative to the extent of the whole set: fewer
  // pairs overlap along it (a chain running north is swept along y).
  double density[2];
  for (int axis = 0; axis < 2; ++axis) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0;
    for (const SweepSegment& s : segments) {
      lo = std::min(lo, s.lo[axis]);
      hi = std::max(hi, s.hi[axis]);
      sum += s.hi[axis] - s.lo[axis];
    }
    density[axis] = hi > lo ? sum / (hi - lo) : std::numeric_limits<double>::infinity();
  }
  const int axis = density[1] < density[0] ? 1 : 0;
  const int other = 1 - axis;
  std::sort(segments.begin(), segments.end(),
            [axis](const SweepSegment& s, const SweepSegment& t) { return s.lo[axis] < t.lo[axis]; });
  for (std::size_t i = 0; i < segments.size(); ++i) {
    const SweepSegment& s = segments[i];
    for (std::size_t j = i + 1; j < segments.size() && segments[j].lo[axis] <= s.hi[axis]; ++j) {
      const SweepSegment& t = segments[j];
      if (t.lo[other] > s.hi[other] || t.hi[other] < s.lo[other]) continue;
      if (!visit(s, t)) return;
    }
  }
}

// A point where two segments known to meet do so (an end of the shared piece when they overlap).
Vec2 meetingPoint(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const auto result = CGAL::intersection(CgalSegment(toCgal(a), toCgal(b)), CgalSegment(toCgal(c), toCgal(d)));
  if (result) {
    if (const Point* p = boost::get<Point>(&*result)) return fromCgal(*p);
    if (const CgalSegment* s = boost::get<CgalSegment>(&*result)) return fromCgal(s->source());
  }
  return a;  // not reached for segments that meet
}

// Adjacent segments [a, v] and [v, c] meet elsewhere than v only when they are collinear and fold
// back over each other. Returns that meeting point (the end nearer to v).
std::optional<Vec2> foldPoint(const Vec2& a, const Vec2& v, const Vec2& c) {
  const Point pa = toCgal(a), pv = toCgal(v), pc = toCgal(c);
  if (CGAL::orientation(pa, pv, pc) != CGAL::COLLINEAR) return std::nullopt;
  if (CGAL::angle(pa, pv, pc) != CGAL::ACUTE) return std::nullopt;
  return (a - v).squaredNorm() <= (c - v).squaredNorm() ? a : c;
}

bool doIntersect(const SweepSegment& s, const SweepSegment& t) {
  return CGAL::do_intersect(CgalSegment(toCgal(s.a), toCgal(s.b)), CgalSegment(toCgal(t.a), toCgal(t.b)));
}

// Self-intersections of one chain; stops after the first hit when `firstOnly`.
std::vector<SegmentHit> chainSelfHits(const std::vector<Vec2>& points, bool closed, bool firstOnly) {
  std::vector<SweepSegment> segments;
  segments.reserve(points.size());
  addChain(points, closed, 0, segments);
  const std::size_t m = segments.size();  // non-zero-length segments
  std::vector<SegmentHit> hits;
  sweepPairs(segments, [&](const SweepSegment& s0, const SweepSegment& t0) {
    const SweepSegment* s = &s0;
    const SweepSegment* t = &t0;
    if (s->rank > t->rank) std::swap(s, t);
    std::optional<Vec2> point;
    if (t->rank == s->rank + 1) {
      point = foldPoint(s->a, s->b, t->b);  // s ends where t starts
    } else if (closed && m > 2 && s->rank == 0 && t->rank == m - 1) {
      point = foldPoint(t->a, t->b, s->b);  // the ring's last segment ends where the first starts
    } else if (doIntersect(*s, *t)) {
      point = meetingPoint(s->a, s->b, t->a, t->b);
    }
    if (point) {
      hits.push_back({s->index, t->index, *point});
      if (firstOnly) return false;
    }
    return true;
  });
  std::sort(hits.begin(), hits.end(),
            [](const SegmentHit& x, const SegmentHit& y) { return x.i != y.i ? x.i < y.i : x.j < y.j; });
  return hits;
}

}  // namespace

double signedArea(const Polygon2& ring) {
  const std::size_t n = ring.size();
  if (n < 3) return 0.0;
  // Relative to the first vertex, for precision far from the origin.
  const Vec2 o = ring.front();
  double twice = 0;
  for (std::size_t i = 1; i + 1 < n; ++i) twice += cross2(ring[i] - o, ring[i + 1] - o);
  return 0.5 * twice;
}

Vec2 centroid(const Polygon2& ring) {
  const std::size_t n = ring.size();
  if (n == 0) return Vec2::Zero();
  const Vec2 o = ring.front();
  double twice = 0;
  Vec2 sum = Vec2::Zero();
  for (std::size_t i = 1; i + 1 < n; ++i) {
    const Vec2 p = ring[i] - o, q = ring[i + 1] - o;
    const double c = cross2(p, q);
    twice += c;
    sum += c * (p + q);
  }
  if (std::abs(twice) > 0) return o + sum / (3.0 * twice);
  // Degenerate (no area): the mean of the vertices.
  Vec2 mean = Vec2::Zero();
  for (const Vec2& p : ring) mean += p;
  return mean / static_cast<double>(n);
}

bool isSimple(const Polygon2& ring) {
  const std::size_t n = ring.size();
  if (n < 3) return false;
  // A repeated vertex makes the edges on either side of the zero-length edge meet.
  for (std::size_t i = 0; i < n; ++i) {
    if (ring[i] == ring[(i + 1) % n]) return false;
  }
  return chainSelfHits(ring, true, true).empty();
}

bool contains(const Polygon2& ring, const Vec2& p) {
  const std::size_t n = ring.size();
  if (n == 0) return false;
  if (n == 1) return ring.front() == p;
  if (n == 2) return segmentsIntersect({ring[0], ring[1]}, {p, p});
  std::vector<Point> pts;
  pts.reserve(n);
  for (const Vec2& v : ring) pts.push_back(toCgal(v));
  return CGAL::bounded_side_2(pts.begin(), pts.end(), toCgal(p), K()) != CGAL::ON_UNBOUNDED_SIDE;
}

namespace {

// countContained for a simple ring by scanlines: the points grouped by their y, each row's edge
// crossings computed once, and a point inside when an odd number of them lies to its right. Exact:
// a point that may lie on the boundary — within `eps` of a crossing, of a vertex on its row or of a
// horizontal edge on its row, the only places a boundary point can be — is decided by CGAL's exact
// test instead, and elsewhere the parity does not depend on the crossings' last bits.
std::size_t countContainedByRows(const Polygon2& ring, const std::vector<Point>& cgal_ring,
                                 const std::vector<Vec2>& points) {
  double scale = 1;
  for (const Vec2& v : ring) scale = std::max({scale, std::abs(v.x()), std::abs(v.y())});
  const double eps = 1e-9 * scale;
  auto exact = [&](const Vec2& p) {
    return CGAL::bounded_side_2(cgal_ring.begin(), cgal_ring.end(), toCgal(p), K()) != CGAL::ON_UNBOUNDED_SIDE;
  };
  std::size_t count = 0;
  std::vector<std::size_t> order;  // the points with a finite y, by y; the others one by one
  order.reserve(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (std::isfinite(points[i].y())) order.push_back(i);
    else count += exact(points[i]);
  }
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return points[a].y() < points[b].y(); });
  std::vector<double> crossings, touches;  // touches: the vertices on the row
  std::vector<std::pair<double, double>> flat;  // the row's horizontal edges, [lo, hi]
  const std::size_t n = ring.size();
  for (std::size_t first = 0; first < order.size();) {
    const double y = points[order[first]].y();
    std::size_t last = first;
    while (last < order.size() && points[order[last]].y() == y) ++last;
    crossings.clear();
    touches.clear();
    flat.clear();
    for (std::size_t i = 0; i < n; ++i) {
      const Vec2 &a = ring[i], &b = ring[(i + 1) % n];
      if (a.y() == y) touches.push_back(a.x());
      if (a.y() == y && b.y() == y) flat.emplace_back(std::min(a.x(), b.x()), std::max(a.x(), b.x()));
      else if ((a.y() > y) != (b.y() > y)) crossings.push_back(a.x() + (y - a.y()) * (b.x() - a.x()) / (b.y() - a.y()));
    }
    std::sort(crossings.begin(), crossings.end());
    std::sort(touches.begin(), touches.end());
    auto near = [&](const std::vector<double>& xs, double x) {
      const auto it = std::lower_bound(xs.begin(), xs.end(), x - eps);
      return it != xs.end() && *it <= x + eps;
    };
    for (std::size_t k = first; k < last; ++k) {
      const Vec2& p = points[order[k]];
      const double x = p.x();
      bool unsure = !std::isfinite(x) || near(crossings, x) || near(touches, x);
      for (const auto& [lo, hi] : flat) unsure = unsure || (x >= lo - eps && x <= hi + eps);
      if (unsure) {
        count += exact(p);
      } else {
        const auto right = crossings.end() - std::upper_bound(crossings.begin(), crossings.end(), x);
        count += right % 2 == 1;
      }
    }
    first = last;
  }
  return count;
}

}  // namespace

std::size_t countContained(const Polygon2& ring, const std::vector<Vec2>& points) {
  std::size_t count = 0;
  if (ring.size() < 3) {
    for (const Vec2& p : points) count += contains(ring, p);
    return count;
  }
  std::vector<Point> pts;
  pts.reserve(ring.size());
  for (const Vec2& v : ring) pts.push_back(toCgal(v));
  // Many points: by rows, when the ring is simple (where bounded_side_2 is defined as inside/outside;
  // its answer for a ring that crosses itself is kept as it was).
  const bool finite = std::all_of(ring.begin(), ring.end(), [](const Vec2& v) { return v.allFinite(); });
  if (points.size() >= 64 && finite && isSimple(ring)) return countContainedByRows(ring, pts, points);
  for (const Vec2& p : points)
    count += CGAL::bounded_side_2(pts.begin(), pts.end(), toCgal(p), K()) != CGAL::ON_UNBOUNDED_SIDE;
  return count;
}

double boundaryDistance(const Polygon2& ring, const Vec2& p) {
  const std::size_t n = ring.size();
  if (n == 0) return std::numeric_limits<double>::infinity();
  if (n == 1) return (ring.front() - p).norm();
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < n; ++i) best = std::min(best, Segment2{ring[i], ring[(i + 1) % n]}.distanceTo(p));
  return best;
}

Polygon2 convexHull(const std::vector<Vec2>& points) {
  std::vector<Point> in;
  in.reserve(points.size());
  for (const Vec2& v : points) in.push_back(toCgal(v));
  std::vector<Point> out;
  CGAL::convex_hull_2(in.begin(), in.end(), std::back_inserter(out), K());
  Polygon2 hull;
  hull.reserve(out.size());
  for (const Point& q : out) hull.push_back(fromCgal(q));
  return hull;
}

Polygon2 counterClockwise(Polygon2 ring) {
  if (signedArea(ring) < 0) std::reverse(ring.begin() + 1, ring.end());  // keeps the first vertex first
  return ring;
}

std::vector<SegmentHit> selfIntersections(const std::vector<Vec2>& points, bool closed) {
  return chainSelfHits(points, closed, false);
}

std::vector<SegmentHit> chainIntersections(const std::vector<Vec2>& a, const std::vector<Vec2>& b) {
  std::vector<SweepSegment> segments;
  segments.reserve(a.size() + b.size());
  addChain(a, false, 0, segments);
  addChain(b, false, 1, segments);
  std::vector<SegmentHit> hits;
  sweepPairs(segments, [&](const SweepSegment& s0, const SweepSegment& t0) {
    if (s0.chain == t0.chain) return true;
    const SweepSegment& s = s0.chain == 0 ? s0 : t0;
    const SweepSegment& t = s0.chain == 0 ? t0 : s0;
    if (doIntersect(s, t)) hits.push_back({s.index, t.index, meetingPoint(s.a, s.b, t.a, t.b)});
    return true;
  });
  std::sort(hits.begin(), hits.end(),
            [](const SegmentHit& x, const SegmentHit& y) { return x.i != y.i ? x.i < y.i : x.j < y.j; });
  return hits;
}

}  // namespace mapnav
