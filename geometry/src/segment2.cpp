#include "mapnav/geometry/segment2.h"
#include "cgal_kernel.h"

#include <algorithm>
#include <cmath>

#include <CGAL/intersections.h>
#include <Eigen/Eigenvalues>

namespace mapnav {

namespace {
using namespace cgal;
using CgalSegment = cgal::Segment;  // beside mapnav's own Segment2
bool degenerate(const Segment2& s) { return s.a == s.b; }
}  // namespace

Vec2 Segment2::direction() const {
  const Vec2 v = b - a;
  const double n = v.norm();
  if (!(n > 0)) return {1.0, 0.0};
  return v / n;
}

double Segment2::heading() const {
  if (degenerate(*this)) return 0.0;
  return std::atan2(b.y() - a.y(), b.x() - a.x());
}

double Segment2::closestParameter(const Vec2& p) const {
  const Vec2 v = b - a;
  const double l2 = v.squaredNorm();
  if (!(l2 > 0)) return 0.0;
  return std::clamp((p - a).dot(v) / l2, 0.0, 1.0);
}

double Segment2::signedDistance(const Vec2& p) const { return cross2(direction(), p - a); }

Box2 Segment2::bounds() const { return Box2(a.cwiseMin(b), a.cwiseMax(b)); }

bool segmentsIntersect(const Segment2& s, const Segment2& t) {
  const bool ds = degenerate(s), dt = degenerate(t);
  if (ds && dt) return s.a == t.a;
  if (ds) return CgalSegment(toCgal(t.a), toCgal(t.b)).has_on(toCgal(s.a));
  if (dt) return CgalSegment(toCgal(s.a), toCgal(s.b)).has_on(toCgal(t.a));
  return CGAL::do_intersect(CgalSegment(toCgal(s.a), toCgal(s.b)), CgalSegment(toCgal(t.a), toCgal(t.b)));
}

std::optional<Vec2> segmentIntersection(const Segment2& s, const Segment2& t) {
  const bool ds = degenerate(s), dt = degenerate(t);
  if (ds || dt) {
    // A point meets the other segment at most at that point.
    if (segmentsIntersect(s, t)) return ds ? s.a : t.a;
    return std::nullopt;
  }
  const CgalSegment cs(toCgal(s.a), toCgal(s.b)), ct(toCgal(t.a), toCgal(t.b));
  const auto result = CGAL::intersection(cs, ct);
  if (!result) return std::nullopt;
  if (const Point* p = boost::get<Point>(&*result)) return fromCgal(*p);
  return std::nullopt;  // overlap along a piece
}

Vec2 principalDirection(const std::vector<Vec2>& points, Vec2& mean) {
  mean = Vec2::Zero();
  for (const Vec2& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  Mat2 c = Mat2::Zero();
  for (const Vec2& p : points) c += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Mat2> es(c);
  Vec2 d = es.eigenvectors().col(1);
  if (d.x() < 0) d = -d;
  return d;
}

double angleBetweenLines(const Segment2& s, const Segment2& t) {
  const Vec2 u = s.direction(), v = t.direction();
  return std::atan2(std::abs(cross2(u, v)), std::abs(u.dot(v)));
}

}  // namespace mapnav
