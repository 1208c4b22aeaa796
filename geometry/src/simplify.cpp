#include "mapnav/geometry/simplify.h"

#include <cmath>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Constrained_triangulation_plus_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
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
