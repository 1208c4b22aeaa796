// Internal to localization/: the point-to-line problem's sample points, re-association, the
// information matrix and its eigen-split (line_problem.h).
#include "line_problem.h"

#include <cmath>

#include <Eigen/Eigenvalues>

#include "mapnav/core/error.h"

namespace mapnav::localization::detail {

Problem::Problem(const std::vector<LineCorrespondence>& l, double max_angle_deg)
    : lines(l), max_angle_rad(degToRad(max_angle_deg)) {
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const LineCorrespondence& c = lines[i];
    if (!(std::isfinite(c.sigma_m) && c.sigma_m > 0)) {
      throw InvalidInput("line correspondence " + c.id + ": sigma_m must be finite and > 0");
    }
    pts.push_back({c.detected_vehicle.a, Vec2::Zero(), 0, c.sigma_m, i});
    pts.push_back({c.detected_vehicle.b, Vec2::Zero(), 0, c.sigma_m, i});
    map_lines.push_back(c.map_world);
    setLine(i, c.map_world);
  }
}

void Problem::setLine(std::size_t i, const Segment2& line) {
  map_lines[i] = line;
  const Vec2 n = leftNormal(line.direction());
  for (PointObs* p : {&pts[2 * i], &pts[2 * i + 1]}) {
    p->n = n;
    p->c = n.dot(line.a);
  }
}

bool Problem::reassociate(const Vec3& s) {
  const Pose2 pose = toPose(s);
  bool changed = false;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const LineCorrespondence& c = lines[i];
    if (c.candidates.empty()) continue;
    const Segment2 placed{pose.transform(c.detected_vehicle.a), pose.transform(c.detected_vehicle.b)};
    const Vec2 mid = placed.pointAt(0.5);
    const Segment2* best = nullptr;
    bool best_aligned = false;
    double best_distance = 0;
    for (const Segment2& candidate : c.candidates) {
      if (candidate.length() < 1e-9) continue;
      const bool aligned = angleBetweenLines(placed, candidate) <= max_angle_rad;
      const double d = candidate.distanceTo(mid);
      if (best == nullptr || (aligned && !best_aligned) || (aligned == best_aligned && d < best_distance)) {
        best = &candidate;
        best_aligned = aligned;
        best_distance = d;
      }
    }
    if (best != nullptr && !(map_lines[i].a == best->a && map_lines[i].b == best->b)) {
      setLine(i, *best);
      changed = true;
    }
  }
  return changed;
}

// J^T W J of the used points at s, W = 1/sigma^2 (no robust weights).
Mat3 informationOf(const std::vector<PointObs>& pts, const std::vector<char>& used, const Vec3& s) {
  Mat3 info = Mat3::Zero();
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (!used[pts[i].line]) continue;
    const Vec3 j = jacobian(pts[i], s);
    info += j * j.transpose() / (pts[i].sigma * pts[i].sigma);
  }
  return info;
}

// Unit eigenvectors of a symmetric 3x3 matrix with eigenvalues at least `threshold` (observed), and
// the others (unobserved, smallest first). Signs fixed (largest component positive) so that results
// are reproducible.
std::pair<Eigen::Matrix<double, 3, Eigen::Dynamic>, std::vector<Vec3>> splitDirections(const Mat3& info,
                                                                                       double threshold) {
  Eigen::SelfAdjointEigenSolver<Mat3> eig(info);
  std::vector<Vec3> observed, unobserved;
  for (int i = 0; i < 3; ++i) {  // ascending eigenvalues
    Vec3 v = eig.eigenvectors().col(i);
    Eigen::Index k = 0;
    v.cwiseAbs().maxCoeff(&k);
    if (v(k) < 0) v = -v;
    (eig.eigenvalues()(i) >= threshold && eig.eigenvalues()(i) > 0 ? observed : unobserved).push_back(v);
  }
  Eigen::Matrix<double, 3, Eigen::Dynamic> u(3, static_cast<Eigen::Index>(observed.size()));
  for (std::size_t i = 0; i < observed.size(); ++i) u.col(static_cast<Eigen::Index>(i)) = observed[i];
  return {u, unobserved};
}

}  // namespace mapnav::localization::detail
