#pragma once
// Internal to localization/: the point-to-line least-squares problem that the line fit
// (line_fit.cpp) and the filter's iterated update (pose_filter.cpp) share — the state as a vector,
// the sample points with their residual and Jacobian, re-association, the information matrix and
// its split into observed and unobserved directions. Not part of the public API.
//
// State s = (x, y, heading) in the world frame: m, m, rad.
#include <cstddef>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "mapnav/geometry/pose2.h"
#include "mapnav/geometry/segment2.h"
#include "mapnav/geometry/types.h"
#include "mapnav/localization/correspondences.h"

namespace mapnav::localization::detail {

// The state (x, y, heading) as a vector, and back.
inline Vec3 toVec(const Pose2& p) { return {p.x(), p.y(), p.heading()}; }
inline Pose2 toPose(const Vec3& v) { return Pose2(v.x(), v.y(), v.z()); }
// a - b with the heading difference wrapped.
inline Vec3 difference(const Vec3& a, const Vec3& b) {
  Vec3 d = a - b;
  d.z() = normalizeAngle(d.z());
  return d;
}

// One sample point: a detected end point v (vehicle frame) that should lie on the world line
// {p : n.p = c}. Its residual at state s = (x, y, h) is r = n.(R(h) v + t) - c.
struct PointObs {
  Vec2 v;
  Vec2 n;
  double c = 0;
  double sigma = 1;
  std::size_t line = 0;  // index of its correspondence
};

inline double residual(const PointObs& o, const Vec3& s) {
  const Vec2 w = Pose2(s.x(), s.y(), s.z()).transform(o.v);
  return o.n.dot(w) - o.c;
}

// dr/ds: (n_x, n_y, n . d(R v)/dh), with d(R v)/dh = leftNormal(R v).
inline Vec3 jacobian(const PointObs& o, const Vec3& s) {
  const Vec2 rv = Pose2(0, 0, s.z()).rotate(o.v);
  return {o.n.x(), o.n.y(), o.n.dot(leftNormal(rv))};
}

// The sample points of correspondences (two per line: points 2i and 2i + 1 are line i's) and the
// map line each is matched against, which re-association may change.
struct Problem {
  const std::vector<LineCorrespondence>& lines;
  double max_angle_rad;
  std::vector<PointObs> pts;
  std::vector<Segment2> map_lines;

  // Throws InvalidInput for a correspondence whose sigma_m is not finite and > 0.
  Problem(const std::vector<LineCorrespondence>& l, double max_angle_deg);

  void setLine(std::size_t i, const Segment2& line);

  // Each correspondence with candidates takes the one nearest to its detected midpoint placed in
  // the world by s, among those within the angle (all when none is). Whether any line changed.
  bool reassociate(const Vec3& s);
};

// J^T W J of the used points at s, W = 1/sigma^2 (no robust weights).
Mat3 informationOf(const std::vector<PointObs>& pts, const std::vector<char>& used, const Vec3& s);

// Unit eigenvectors of a symmetric 3x3 matrix with eigenvalues at least `threshold` (observed), and
// the others (unobserved, smallest first). Signs fixed (largest component positive) so that results
// are reproducible.
std::pair<Eigen::Matrix<double, 3, Eigen::Dynamic>, std::vector<Vec3>> splitDirections(const Mat3& info,
                                                                                       double threshold);

}  // namespace mapnav::localization::detail
