#include "mapnav/geometry/clip.h"

#include <algorithm>
#include <cmath>
#include <optional>

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

// Counter-clockwise and strictly convex: every turn to the left, and the turns add up to one turn
// round (more would be a star, which turns left everywhere too).
bool strictlyConvex(const Polygon2& ring) {
  const std::size_t n = ring.size();
  if (n < 3) return false;
  double turning = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2 e0 = ring[(i + 1) % n] - ring[i], e1 = ring[(i + 2) % n] - ring[(i + 1) % n];
    const double turn = cross2(e0, e1);
    if (!(turn > 0)) return false;
    turning += std::atan2(turn, e0.dot(e1));
  }
  return turning < 3 * kPi;  // 2 pi for a convex ring, at least 4 pi for a star
}

// A crossing of the subject's outline with the clip line: where along the line, and which stretch
// of the subject inside the half-plane (a run) it begins (an entry) or ends (an exit).
struct Crossing {
  double along = 0;  // d . (point - c)
  double tie = 0;    // orders crossings at one vertex on the line (below)
  bool exit = false;
  std::size_t run = 0;
};

void appendPoint(Polygon2& ring, const Vec2& p) {
  if (ring.empty() || ring.back() != p) ring.push_back(p);
}

// The pieces of the simple counter-clockwise `ring` in the closed half-plane left of the line
// through c along d, as the exact, regularized intersection has them. Points exactly on the line
// count as outside: the line is taken as moved inwards by an infinitesimal, so that no vertex lies
// on it and every crossing is a proper one, and the pieces are the limits of those of the smaller
// half-plane (moved outwards, an edge of the ring along the line from outside would join pieces by
// a zero-width bridge). For a simple ring, the crossings sorted along the line alternate exit,
// entry, exit, ... (from an exit the line runs along d inside the ring), so each piece follows the
// ring from an entry to its exit, then the line to the next crossing along it, an entry, and so on
// until it closes. nullopt when rounding breaks the alternation or a product overflows.
std::optional<std::vector<Polygon2>> clipToHalfPlane(const Polygon2& ring, const Vec2& c, const Vec2& d) {
  const std::size_t n = ring.size();
  std::vector<double> side(n);
  std::size_t outside = n;
  for (std::size_t i = 0; i < n; ++i) {
    side[i] = cross2(d, ring[i] - c);
    if (!std::isfinite(side[i])) return std::nullopt;  // overflow: coordinates near the double limit
    if (side[i] <= 0) outside = i;
  }
  if (outside == n) return std::vector<Polygon2>{ring};

  std::vector<Polygon2> runs;  // stretches of the ring inside, from an entry crossing to an exit
  std::vector<Crossing> crossings;
  // Where the edge a -> b meets the line (a vertex on it is the crossing itself), and the crossing
  // of runs.back() there.
  auto crossingOf = [&](const Vec2& a, const Vec2& b, double sa, double sb, bool exit) {
    const Vec2 p = sa == 0 ? a : sb == 0 ? b : Vec2(a + (b - a) * (sa / (sa - sb)));
    // Moved inwards by epsilon, the line meets the edge at p + epsilon (b - a) / (sb - sa): this
    // orders two crossings at one vertex on the line.
    crossings.push_back(Crossing{d.dot(p - c), d.dot(b - a) / (sb - sa), exit, runs.size() - 1});
    return p;
  };
  for (std::size_t k = 0; k < n; ++k) {  // from an outside vertex, so that every run opens first
    const std::size_t i = (outside + k) % n, j = (i + 1) % n;
    const Vec2 &a = ring[i], &b = ring[j];
    const double sa = side[i], sb = side[j];
    if (sa <= 0 && sb > 0) {
      runs.emplace_back();
      runs.back().push_back(crossingOf(a, b, sa, sb, false));
    }
    if (sb > 0) appendPoint(runs.back(), b);
    if (sa > 0 && sb <= 0) appendPoint(runs.back(), crossingOf(a, b, sa, sb, true));
  }

  const bool finite = std::all_of(crossings.begin(), crossings.end(), [](const Crossing& x) {
    return std::isfinite(x.along) && std::isfinite(x.tie);
  });
  if (!finite) return std::nullopt;  // overflow again; and the sort needs numbers
  std::sort(crossings.begin(), crossings.end(), [](const Crossing& x, const Crossing& y) {
    return x.along < y.along || (x.along == y.along && x.tie < y.tie);
  });
  std::vector<std::size_t> next(runs.size(), runs.size());  // the run the line leads to from a run's exit
  for (std::size_t k = 0; k < crossings.size(); k += 2) {
    if (k + 1 >= crossings.size() || !crossings[k].exit || crossings[k + 1].exit) return std::nullopt;
    next[crossings[k].run] = crossings[k + 1].run;
  }

  std::vector<Polygon2> pieces;
  std::vector<bool> used(runs.size(), false);
  for (std::size_t first = 0; first < runs.size(); ++first) {
    if (used[first]) continue;
    Polygon2 piece;
    std::size_t r = first;
    do {
      if (r >= runs.size() || used[r]) return std::nullopt;  // not a cycle back to the first run
      used[r] = true;
      for (const Vec2& p : runs[r]) appendPoint(piece, p);
      r = next[r];
    } while (r != first);
    while (piece.size() > 1 && piece.back() == piece.front()) piece.pop_back();
    if (piece.size() >= 3) pieces.push_back(std::move(piece));
  }
  return pieces;
}

}  // namespace

std::vector<Polygon2> intersectWithConvex(const Polygon2& subject, const Polygon2& clip) {
  if (!allFinite(subject) || !allFinite(clip) || !isSimple(subject)) return {};
  const Polygon2 window = counterClockwise(clip);
  if (!strictlyConvex(window)) return intersectPolygons(subject, clip);
  std::vector<Polygon2> pieces{counterClockwise(subject)};
  for (std::size_t k = 0; k < window.size() && !pieces.empty(); ++k) {
    const Vec2& c = window[k];
    const Vec2 d = window[(k + 1) % window.size()] - c;
    std::vector<Polygon2> cut;
    for (const Polygon2& piece : pieces) {
      const auto parts = clipToHalfPlane(piece, c, d);
      if (!parts) return intersectPolygons(subject, clip);
      cut.insert(cut.end(), parts->begin(), parts->end());
    }
    pieces = std::move(cut);
  }
  return pieces;
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
