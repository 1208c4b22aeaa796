#include "mapnav/geometry/simplify.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_plus_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Modifiable_priority_queue.h>
#include <CGAL/Polyline_simplification_2/simplify.h>

namespace mapnav {

namespace {
namespace PS = CGAL::Polyline_simplification_2;
using K = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = K::Point_2;
using Vb = PS::Vertex_base_2<K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K>;
using TDS = CGAL::Triangulation_data_structure_2<Vb, Fb>;
// Exact_predicates_tag: a polyline that crosses itself gets its crossing points as constraint vertices.
using CDT = CGAL::Constrained_Delaunay_triangulation_2<K, TDS, CGAL::Exact_predicates_tag>;
using CT = CGAL::Constrained_triangulation_plus_2<CDT>;
}  // namespace

std::vector<Vec2> simplifyPolyline(const std::vector<Vec2>& points, double tolerance) {
  if (points.size() < 3 || !(tolerance >= 0) || !std::isfinite(tolerance)) return points;
  for (const Vec2& p : points) {
    if (!p.allFinite()) return points;
  }

  std::vector<Point> input;
  input.reserve(points.size());
  for (const Vec2& p : points) input.emplace_back(p.x(), p.y());

  CT ct;
  // Consecutive repeated points are merged by the triangulation; a closed polyline (first == last)
  // becomes a closed constraint whose first vertex stays fixed.
  const CT::Constraint_id cid = ct.insert_constraint(input.begin(), input.end());
  if (cid == nullptr) return {points.front()};  // all points equal

  PS::simplify(ct, cid, PS::Squared_distance_cost(), PS::Stop_above_cost_threshold(tolerance * tolerance));

  std::vector<Vec2> out;
  for (auto it = ct.vertices_in_constraint_begin(cid); it != ct.vertices_in_constraint_end(cid); ++it) {
    const Point& p = (*it)->point();
    out.emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()));
  }
  return out;
}

}  // namespace mapnav

namespace mapnav {

namespace {

// The first `m` points of a chain of integer points in a grid of kCell-pixel cells: each cell's
// points (their indices, in order) are members[start[c]] .. members[start[c + 1] - 1].
struct CellGrid {
  static constexpr long kCell = 8;
  long x0 = 0, y0 = 0, x1 = 0, y1 = 0, gw = 0, gh = 0;
  std::vector<std::size_t> start, members;

  CellGrid(const std::vector<Vec2>& points, std::size_t m) : members(m) {
    x0 = x1 = static_cast<long>(points[0].x());
    y0 = y1 = static_cast<long>(points[0].y());
    for (std::size_t i = 0; i < m; ++i) {
      const long x = static_cast<long>(points[i].x()), y = static_cast<long>(points[i].y());
      x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
    }
    gw = (x1 - x0) / kCell + 1, gh = (y1 - y0) / kCell + 1;
    start.assign(static_cast<std::size_t>(gw * gh) + 1, 0);
    for (std::size_t i = 0; i < m; ++i) ++start[cellOf(points[i]) + 1];
    for (std::size_t c = 1; c < start.size(); ++c) start[c] += start[c - 1];
    std::vector<std::size_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < m; ++i) members[fill[cellOf(points[i])]++] = i;
  }
  std::size_t cellOf(long x, long y) const { return static_cast<std::size_t>(((y - y0) / kCell) * gw + (x - x0) / kCell); }
  std::size_t cellOf(const Vec2& p) const { return cellOf(static_cast<long>(p.x()), static_cast<long>(p.y())); }
  /// The index of the first of the points at (x, y), or -1.
  long find(const std::vector<Vec2>& points, double x, double y) const {
    if (x < x0 || x > x1 || y < y0 || y > y1) return -1;
    const std::size_t c = cellOf(static_cast<long>(x), static_cast<long>(y));
    for (std::size_t k = start[c]; k < start[c + 1]; ++k)
      if (points[members[k]].x() == x && points[members[k]].y() == y) return static_cast<long>(members[k]);
    return -1;
  }
};

// Integer coordinates of moderate size, 8-neighbour steps: the chain's points fit a CellGrid.
bool isIntegerChain(const std::vector<Vec2>& points) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec2& p = points[i];
    if (!(std::abs(p.x()) < 1e6 && std::abs(p.y()) < 1e6) || p.x() != std::floor(p.x()) || p.y() != std::floor(p.y()))
      return false;
    if (i + 1 < points.size()) {
      const Vec2 d = points[i + 1] - p;
      if (std::abs(d.x()) > 1 || std::abs(d.y()) > 1 || (d.x() == 0 && d.y() == 0)) return false;
    }
  }
  return true;
}

// A chain that simplifyPixelChain handles itself: an integer chain (above) with no repeated point
// but a ring's closing one, no two diagonal steps crossing in a pixel square. Then every vertex of
// CGAL's triangulation is a chain point with two constrained edges, no constraint passes through
// another vertex, and CGAL's removal test is "no other vertex in the closed triangle". `grid`: the
// chain's points but a ring's closing one.
bool isPixelChain(const std::vector<Vec2>& points, const CellGrid& grid) {
  const std::size_t n = points.size();
  const bool closed = points.front() == points.back();
  const long m = closed ? static_cast<long>(n) - 1 : static_cast<long>(n);
  if (closed && m < 3) return false;  // a ring of two points runs one edge twice
  for (long i = 0; i < m; ++i)
    if (grid.find(points, points[i].x(), points[i].y()) != i) return false;  // an earlier point is there
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Vec2 a = points[i], b = points[i + 1];
    if (a.x() == b.x() || a.y() == b.y()) continue;
    const long c = grid.find(points, a.x(), b.y()), d = grid.find(points, b.x(), a.y());  // the other diagonal
    if (c < 0 || d < 0) continue;
    const long gap = std::abs(c - d);
    if (gap == 1 || (closed && gap == m - 1)) return false;
  }
  return true;
}

// CGAL::squared_distance(Segment_2(s, t), p) for Epick, operation for operation (CGAL 5.5's
// internal::squared_distance(Point_2, Segment_2) and line_from_pointsC2), so that the costs, and with
// them the queue's order, are bit for bit CGAL's; inline, with the segment's terms computed once.
struct SegmentDistance {
  double sx, sy, tx, ty, ex, ey, e, a, b, c, ab;
  SegmentDistance(double sx_, double sy_, double tx_, double ty_) : sx(sx_), sy(sy_), tx(tx_), ty(ty_) {
    ex = tx - sx, ey = ty - sy;
    e = ex * ex + ey * ey;
    if (sy == ty) {  // line_from_pointsC2: horizontal and vertical lines exactly
      a = 0;
      b = tx > sx ? 1 : (tx == sx ? 0 : -1);
      c = tx > sx ? -sy : (tx == sx ? 0 : sy);
    } else if (tx == sx) {
      b = 0;
      a = ty > sy ? -1 : 1;
      c = ty > sy ? sx : -sx;
    } else {
      a = sy - ty;
      b = tx - sx;
      c = -sx * a - sy * b;
    }
    ab = a * a + b * b;
  }
  /// The largest squared distance of points[first, last) to the segment, 0 for none. The distance
  /// to the line is (n * n) / ab as in CGAL; the division is done once, for the largest n * n, which
  /// is the same value (dividing by ab > 0 rounds monotonically).
  double farthest(const std::vector<Vec2>& points, std::size_t first, std::size_t last) const {
    double ends = 0.0, line = 0.0;
    for (std::size_t i = first; i < last; ++i) {
      const double px = points[i].x(), py = points[i].y();
      const double dx = px - sx, dy = py - sy;
      const double d = dx * ex + dy * ey;
      if (d <= 0) {
        ends = (std::max)(ends, dx * dx + dy * dy);
      } else if (d > e) {
        const double fx = px - tx, fy = py - ty;
        ends = (std::max)(ends, fx * fx + fy * fy);
      } else {
        const double n = a * px + b * py + c;
        line = (std::max)(line, n * n);
      }
    }
    return (std::max)(ends, line / ab);  // s == t: ab = 0, no point reaches the last branch, 0 / 0 is ignored
  }
};

}  // namespace

std::vector<Vec2> simplifyPixelChain(const std::vector<Vec2>& points, double tolerance) {
  return std::move(simplifyPixelChainAt(points, {tolerance}).front());
}

std::vector<std::vector<Vec2>> simplifyPixelChainAt(const std::vector<Vec2>& points,
                                                    const std::vector<double>& tolerances) {
  // The tolerances in ascending order (`order`), those simplifyPolyline would not simplify at
  // (negative, NaN, infinite; a chain of fewer than 3 points) answered at once.
  std::vector<std::vector<Vec2>> out(tolerances.size());
  std::vector<std::size_t> order;
  for (std::size_t k = 0; k < tolerances.size(); ++k) {
    if (points.size() < 3 || !(tolerances[k] >= 0) || !std::isfinite(tolerances[k])) out[k] = points;
    else order.push_back(k);
  }
  if (order.empty()) return out;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return tolerances[a] < tolerances[b]; });
  const auto byCgal = [&] {
    for (const std::size_t k : order) out[k] = simplifyPolyline(points, tolerances[k]);
    return out;
  };
  if (!isIntegerChain(points)) return byCgal();
  const std::size_t n = points.size();
  const bool closed = points.front() == points.back();
  // The remaining vertices in a grid of 8-pixel cells (removed ones are skipped, not erased).
  const CellGrid grid(points, closed ? n - 1 : n);
  if (!isPixelChain(points, grid)) return byCgal();

  std::vector<Point> pt;
  pt.reserve(n);
  for (const Vec2& p : points) pt.emplace_back(p.x(), p.y());
  // A ring's last point is its first vertex.
  const auto vertex = [&](std::size_t i) { return closed && i == n - 1 ? std::size_t{0} : i; };

  std::vector<std::size_t> prev(n), next(n);
  for (std::size_t i = 0; i < n; ++i) prev[i] = i == 0 ? 0 : i - 1, next[i] = i + 1 == n ? n - 1 : i + 1;
  std::vector<char> alive(n, 1);
  std::vector<double> cost(n, 0.0);
  const auto removable = [&](std::size_t i) { return i != 0 && i != n - 1; };

  // CGAL's Squared_distance_cost: the largest squared distance of the original points between the
  // neighbours to the segment joining them.
  const auto costOf = [&](std::size_t q) {
    const Vec2 &s = points[prev[q]], &t = points[next[q]];
    return SegmentDistance(s.x(), s.y(), t.x(), t.y()).farthest(points, prev[q] + 1, next[q]);
  };
  // CGAL's removal test (Polyline_simplification_2::is_removable) on these chains.
  const auto canRemove = [&](std::size_t q) {
    const std::size_t u = prev[q], w = next[q];
    const CGAL::Orientation o = CGAL::orientation(pt[u], pt[q], pt[w]);
    if (o == CGAL::COLLINEAR) return true;
    if (vertex(next[w]) == vertex(u) || vertex(prev[u]) == vertex(w)) return false;  // u-w is a constraint
    const long bx0 = static_cast<long>(std::min({points[u].x(), points[q].x(), points[w].x()}));
    const long bx1 = static_cast<long>(std::max({points[u].x(), points[q].x(), points[w].x()}));
    const long by0 = static_cast<long>(std::min({points[u].y(), points[q].y(), points[w].y()}));
    const long by1 = static_cast<long>(std::max({points[u].y(), points[q].y(), points[w].y()}));
    const CGAL::Orientation away = o == CGAL::LEFT_TURN ? CGAL::RIGHT_TURN : CGAL::LEFT_TURN;
    constexpr long kCell = CellGrid::kCell;
    for (long cy = (by0 - grid.y0) / kCell; cy <= (by1 - grid.y0) / kCell; ++cy) {
      for (long cx = (bx0 - grid.x0) / kCell; cx <= (bx1 - grid.x0) / kCell; ++cx) {
        const std::size_t c = static_cast<std::size_t>(cy * grid.gw + cx);
        for (std::size_t k = grid.start[c]; k < grid.start[c + 1]; ++k) {
          const std::size_t x = grid.members[k];
          if (!alive[x] || x == vertex(u) || x == q || x == vertex(w)) continue;
          const Vec2& p = points[x];
          if (p.x() < bx0 || p.x() > bx1 || p.y() < by0 || p.y() > by1) continue;
          if (CGAL::orientation(pt[u], pt[q], pt[x]) != away && CGAL::orientation(pt[q], pt[w], pt[x]) != away &&
              CGAL::orientation(pt[w], pt[u], pt[x]) != away)
            return false;  // in the closed triangle
        }
      }
    }
    return true;
  };

  struct ByCost {
    const std::vector<double>* cost;
    bool operator()(std::size_t a, std::size_t b) const { return (*cost)[a] < (*cost)[b]; }
  };
  CGAL::Modifiable_priority_queue<std::size_t, ByCost, boost::identity_property_map> queue(n, ByCost{&cost});
  for (std::size_t i = 0; i < n; ++i) {
    if (!removable(i)) continue;
    cost[i] = costOf(i);
    if (!queue.contains(i)) queue.push(i);
  }
  const auto refresh = [&](std::size_t i) {
    if (!removable(i)) return;
    cost[i] = costOf(i);
    if (queue.contains(i)) queue.update(i);
    else queue.push(i);
  };
  // The vertices left, written out as the answer at order[next_answer]'s tolerance.
  std::size_t next_answer = 0;
  const auto answer = [&] {
    std::vector<Vec2>& chain = out[order[next_answer++]];
    for (std::size_t i = 0;; i = next[i]) {
      chain.push_back(points[i]);
      if (i == n - 1) break;
    }
  };
  // CGAL's loop with Stop_above_cost_threshold(tolerance²) stops at the first vertex popped whose
  // cost reaches it; up to there every larger tolerance's loop is the same, so it goes on from there.
  while (!queue.empty()) {
    const std::size_t q = queue.top();
    queue.pop();
    while (next_answer < order.size() && cost[q] >= tolerances[order[next_answer]] * tolerances[order[next_answer]])
      answer();
    if (next_answer == order.size()) break;
    if (!canRemove(q)) continue;
    const std::size_t u = prev[q], w = next[q];
    alive[q] = 0;
    next[u] = w;
    prev[w] = u;
    refresh(u);
    refresh(w);
  }
  while (next_answer < order.size()) answer();  // the queue ran out first: what is left
  return out;
}

}  // namespace mapnav
