#include "mapnav/map/matching.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <boost/math/distributions/chi_squared.hpp>

#include "mapnav/core/error.h"
#include "mapnav/core/options.h"
#include "mapnav/geometry/camera.h"
#include "mapnav/map/map.h"
#include "mapnav/map/predict.h"
#include "mapnav/vision_iface/detected_object.h"

namespace mapnav {

// ---------------------------------------------------------------------------------------------
// Enums and options

std::string_view toString(RobustLoss loss) {
  switch (loss) {
    case RobustLoss::None: return "none";
    case RobustLoss::Huber: return "huber";
    case RobustLoss::Cauchy: return "cauchy";
  }
  return "none";
}

std::optional<RobustLoss> robustLossFromString(std::string_view text) {
  for (RobustLoss l : {RobustLoss::None, RobustLoss::Huber, RobustLoss::Cauchy}) {
    if (toString(l) == text) return l;
  }
  return std::nullopt;
}

std::string_view toString(PositionStatus status) {
  switch (status) {
    case PositionStatus::Corrected: return "corrected";
    case PositionStatus::OdometryOnly: return "odometry-only";
    case PositionStatus::Rejected: return "rejected";
  }
  return "odometry-only";
}

std::optional<PositionStatus> positionStatusFromString(std::string_view text) {
  for (PositionStatus s : {PositionStatus::Corrected, PositionStatus::OdometryOnly, PositionStatus::Rejected}) {
    if (toString(s) == text) return s;
  }
  return std::nullopt;
}

void LineMatchOptions::validate() const {
  auto require = [](bool ok, const char* field, double value, const char* rule) {
    requireOption(ok, "LineMatchOptions", field, value, rule);
  };
  require(std::isfinite(loss_scale) && loss_scale > 0, "loss_scale", loss_scale, "finite and > 0");
  require(std::isfinite(inlier_threshold) && inlier_threshold > 0, "inlier_threshold", inlier_threshold,
          "finite and > 0");
  require(max_iterations >= 1, "max_iterations", max_iterations, ">= 1");
  require(std::isfinite(step_tolerance) && step_tolerance > 0, "step_tolerance", step_tolerance, "finite and > 0");
  require(std::isfinite(min_information) && min_information >= 0, "min_information", min_information,
          "finite and >= 0");
  require(reassociate_max_angle_deg > 0 && reassociate_max_angle_deg <= 90, "reassociate_max_angle_deg",
          reassociate_max_angle_deg, "in (0, 90]");
}

void MotionNoiseOptions::validate() const {
  auto require = [](double value, const char* field) {
    requireOption(std::isfinite(value) && value >= 0, "MotionNoiseOptions", field, value, "finite and >= 0");
  };
  require(distance_sigma_per_m, "distance_sigma_per_m");
  require(heading_sigma_per_rad, "heading_sigma_per_rad");
  require(heading_sigma_per_m, "heading_sigma_per_m");
  require(base_sigma_m, "base_sigma_m");
  require(base_heading_sigma_rad, "base_heading_sigma_rad");
}

void FilterOptions::validate() const {
  match.validate();
  motion.validate();
  requireOption(gate_probability > 0 && gate_probability < 1, "FilterOptions", "gate_probability", gate_probability,
                "in (0, 1)");
  requireOption(update_iterations >= 1, "FilterOptions", "update_iterations", update_iterations, ">= 1");
}

void LocalizeOptions::validate() const {
  auto require = [](bool ok, const char* field, double value, const char* rule) {
    requireOption(ok, "LocalizeOptions", field, value, rule);
  };
  require(std::isfinite(edge_sigma_m) && edge_sigma_m > 0, "edge_sigma_m", edge_sigma_m, "finite and > 0");
  require(std::isfinite(centerline_sigma_m) && centerline_sigma_m > 0, "centerline_sigma_m", centerline_sigma_m,
          "finite and > 0");
  require(std::isfinite(min_line_length_m) && min_line_length_m >= 0, "min_line_length_m", min_line_length_m,
          "finite and >= 0");
  require(std::isfinite(centerline_search_m) && centerline_search_m > 0, "centerline_search_m", centerline_search_m,
          "finite and > 0");
  require(std::isfinite(curve_piece_m) && curve_piece_m >= 0, "curve_piece_m", curve_piece_m, "finite and >= 0");
  require(std::isfinite(edge_sigma_px) && edge_sigma_px >= 0, "edge_sigma_px", edge_sigma_px, "finite and >= 0");
}

// ---------------------------------------------------------------------------------------------
// The least-squares problem

namespace {

// The state (x, y, heading) as a vector, and back.
Vec3 toVec(const Pose2& p) { return {p.x(), p.y(), p.heading()}; }
Pose2 toPose(const Vec3& v) { return Pose2(v.x(), v.y(), v.z()); }
// a - b with the heading difference wrapped.
Vec3 difference(const Vec3& a, const Vec3& b) {
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

double residual(const PointObs& o, const Vec3& s) {
  const Vec2 w = Pose2(s.x(), s.y(), s.z()).transform(o.v);
  return o.n.dot(w) - o.c;
}

// dr/ds: (n_x, n_y, n . d(R v)/dh), with d(R v)/dh = leftNormal(R v).
Vec3 jacobian(const PointObs& o, const Vec3& s) {
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

  Problem(const std::vector<LineCorrespondence>& l, double max_angle_deg) : lines(l), max_angle_rad(degToRad(max_angle_deg)) {
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

  void setLine(std::size_t i, const Segment2& line) {
    map_lines[i] = line;
    const Vec2 n = leftNormal(line.direction());
    for (PointObs* p : {&pts[2 * i], &pts[2 * i + 1]}) {
      p->n = n;
      p->c = n.dot(line.a);
    }
  }

  // Each correspondence with candidates takes the one nearest to its detected midpoint placed in
  // the world by s, among those within the angle (all when none is). Whether any line changed.
  bool reassociate(const Vec3& s) {
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
};

// The loss of a normalised residual u, and its IRLS weight rho'(u)/u.
double lossValue(RobustLoss loss, double k, double u) {
  const double a = std::abs(u);
  switch (loss) {
    case RobustLoss::None: return 0.5 * u * u;
    case RobustLoss::Huber: return a <= k ? 0.5 * u * u : k * a - 0.5 * k * k;
    case RobustLoss::Cauchy: return 0.5 * k * k * std::log1p((u / k) * (u / k));
  }
  return 0.5 * u * u;
}

double lossWeight(RobustLoss loss, double k, double u) {
  const double a = std::abs(u);
  switch (loss) {
    case RobustLoss::None: return 1.0;
    case RobustLoss::Huber: return a <= k ? 1.0 : k / a;
    case RobustLoss::Cauchy: return 1.0 / (1.0 + (u / k) * (u / k));
  }
  return 1.0;
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

struct SolveResult {
  Vec3 state;
  int iterations = 0;
  bool converged = false;
};

// Minimises sum rho(r_i / sigma_i) over the used points by Gauss-Newton with IRLS weights and
// Levenberg damping, starting at `s`. Steps stay in the span of the observed directions of the
// unweighted information, so that unobserved directions keep their starting value.
// Re-associates (Problem::reassociate) at every iterate.
SolveResult solve(Problem& problem, const std::vector<char>& used, Vec3 s, RobustLoss loss,
                  const LineMatchOptions& o) {
  const std::vector<PointObs>& pts = problem.pts;
  const double k = o.loss_scale;
  auto cost = [&](const Vec3& state) {
    double sum = 0;
    for (const PointObs& p : pts) {
      if (used[p.line]) sum += lossValue(loss, k, residual(p, state) / p.sigma);
    }
    return sum;
  };
  SolveResult result{s, 0, false};
  problem.reassociate(s);
  double current = cost(s);
  for (int it = 0; it < o.max_iterations; ++it) {
    // The observed subspace U, from the unweighted information at s.
    const auto [u, unobserved] = splitDirections(informationOf(pts, used, s), o.min_information);
    if (u.cols() == 0) {
      result.converged = true;
      break;
    }
    Mat3 a = Mat3::Zero();
    Vec3 g = Vec3::Zero();
    for (const PointObs& p : pts) {
      if (!used[p.line]) continue;
      const double r = residual(p, s);
      const double w = lossWeight(loss, k, r / p.sigma) / (p.sigma * p.sigma);
      const Vec3 j = jacobian(p, s);
      a += w * j * j.transpose();
      g += w * j * r;
    }
    const Eigen::MatrixXd au = u.transpose() * a * u;
    const Eigen::VectorXd gu = u.transpose() * g;
    const double scale = std::max(au.diagonal().maxCoeff(), 1e-12);
    double mu = 0;  // Levenberg damping: 0 is a Gauss-Newton step
    bool accepted = false;
    Vec3 step = Vec3::Zero();
    for (int attempt = 0; attempt < 12; ++attempt) {
      const Eigen::MatrixXd damped = au + mu * Eigen::MatrixXd::Identity(au.rows(), au.cols());
      step = u * damped.ldlt().solve(-gu);
      Vec3 next = s + step;
      next.z() = normalizeAngle(next.z());
      const double next_cost = cost(next);
      if (next_cost <= current + 1e-12 * (1 + current)) {
        s = next;
        current = next_cost;
        accepted = true;
        // The new iterate may lie nearer other candidates: the cost to beat is theirs then.
        if (problem.reassociate(s)) current = cost(s);
        break;
      }
      mu = mu == 0 ? 1e-4 * scale : 10 * mu;
    }
    ++result.iterations;
    if (!accepted || step.norm() < o.step_tolerance) {
      result.converged = true;  // no step lowers the cost: a minimum (to rounding)
      break;
    }
  }
  result.state = s;
  return result;
}

// The correspondences all of whose points lie within the inlier threshold at s.
std::vector<char> inliersAt(const std::vector<PointObs>& pts, std::size_t line_count, const Vec3& s, double threshold) {
  std::vector<char> ok(line_count, 1);
  for (const PointObs& p : pts) {
    if (std::abs(residual(p, s)) > threshold * p.sigma) ok[p.line] = 0;
  }
  return ok;
}

}  // namespace

Observability observability(const Mat3& information, double heading, double min_information) {
  Observability out;
  const auto [observed, unobserved] = splitDirections(information, min_information);
  out.unobserved = unobserved;
  // A direction is observed when its component in the unobserved span is below sin 45°.
  auto isObserved = [&](const Vec3& d) {
    double hidden = 0;
    for (const Vec3& n : out.unobserved) hidden += n.dot(d) * n.dot(d);
    return hidden < 0.5;
  };
  const Vec2 f = unitVector(heading);
  out.along = isObserved(Vec3(f.x(), f.y(), 0));
  out.lateral = isObserved(Vec3(-f.y(), f.x(), 0));
  out.heading = isObserved(Vec3(0, 0, 1));
  return out;
}

std::optional<LineFit> fitPoseToLines(const Pose2& prior, const std::vector<LineCorrespondence>& lines,
                                      const LineMatchOptions& options) {
  options.validate();
  if (lines.empty()) return std::nullopt;
  Problem problem(lines, options.reassociate_max_angle_deg);
  const std::vector<PointObs>& pts = problem.pts;
  std::vector<char> used(lines.size(), 1);
  LineFit fit;

  // Robust stage: Huber (convex) first; Cauchy from the Huber solution.
  Vec3 s = toVec(prior);
  const RobustLoss first = options.loss == RobustLoss::None ? RobustLoss::None : RobustLoss::Huber;
  SolveResult r = solve(problem, used, s, first, options);
  fit.iterations += r.iterations;
  if (options.loss == RobustLoss::Cauchy) {
    r = solve(problem, used, r.state, RobustLoss::Cauchy, options);
    fit.iterations += r.iterations;
  }

  // Inliers, then plain least squares on them; lines that the least-squares pose puts back within
  // the threshold are readmitted (and the others dropped) until the set settles.
  used = inliersAt(pts, lines.size(), r.state, options.inlier_threshold);
  for (int round = 0;; ++round) {
    if (std::find(used.begin(), used.end(), 1) == used.end()) return std::nullopt;
    r = solve(problem, used, r.state, RobustLoss::None, options);
    fit.iterations += r.iterations;
    if (round == 4) break;
    std::vector<char> next = inliersAt(pts, lines.size(), r.state, options.inlier_threshold);
    if (next == used) break;
    used = std::move(next);
  }
  fit.converged = r.converged;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (used[i]) {
      ++fit.inliers;
    } else {
      fit.outliers.push_back(lines[i].id);
      fit.outlier_indices.push_back(i);
    }
  }

  fit.pose = toPose(r.state);
  fit.map_lines = problem.map_lines;
  fit.information = informationOf(pts, used, r.state);
  double sum = 0;
  int n = 0;
  for (const PointObs& p : pts) {
    if (!used[p.line]) continue;
    const double e = residual(p, r.state);
    sum += e * e;
    ++n;
  }
  fit.rms_m = std::sqrt(sum / n);
  fit.observed = observability(fit.information, fit.pose.heading(), options.min_information);
  return fit;
}

namespace {

/// Calls `use(line, predicted segment index)` for every detected line that is labelled with a
/// predicted segment, not cut by the frame, and at least `min_length_m` long.
template <typename Use>
void forEachLabelledLine(const Prediction& prediction, const DetectedObject& detected, double min_length_m, Use use) {
  if (detected.status != DetectedObject::Status::Ok) return;
  std::map<std::string, std::size_t, std::less<>> index;
  const std::size_t n = std::min(prediction.view.segments.size(), prediction.segments_world.size());
  for (std::size_t i = 0; i < n; ++i) index.emplace(prediction.view.segments[i].id, i);
  for (const DetectedLine& line : detected.lines) {
    if (!line.label || line.frame_edge || line.vehicle.length() < min_length_m) continue;
    const auto it = index.find(*line.label);
    if (it != index.end()) use(line, it->second);
  }
}

}  // namespace

std::vector<LineCorrespondence> labelledCorrespondences(const Prediction& prediction, const DetectedObject& detected,
                                                        double sigma_m, double min_length_m) {
  std::vector<LineCorrespondence> out;
  forEachLabelledLine(prediction, detected, min_length_m, [&](const DetectedLine& line, std::size_t i) {
    out.push_back({*line.label, line.vehicle, prediction.segments_world[i], sigma_m, {}});
  });
  return out;
}

std::vector<LineCorrespondence> edgeCorrespondences(const Map& map, const Prediction& prediction,
                                                    const DetectedObject& detected, const Pose2& prior,
                                                    double sigma_m, double min_length_m, double piece_m) {
  std::vector<LineCorrespondence> out;
  forEachLabelledLine(prediction, detected, min_length_m, [&](const DetectedLine& line, std::size_t i) {
    const InterestSegment& segment = prediction.view.segments[i];
    const Segment2& chord = prediction.segments_world[i];
    const Road* road = (segment.side == "left" || segment.side == "right") ? map.findRoad(segment.owner) : nullptr;
    const Polyline2* edge = road == nullptr ? nullptr : &(segment.side == "left" ? map.leftEdge(*road) : map.rightEdge(*road));
    if (edge == nullptr || edge->segmentCount() == 0 || !(piece_m > 0)) {
      out.push_back({*line.label, line.vehicle, chord, sigma_m, {}});
      return;
    }
    // The stretch of the edge the predicted segment covers: the edge does not go on inside the
    // paved areas the prediction cut it at (a crossing road, an intersection's mouth).
    const double sa = edge->project(chord.a).arc_length, sb = edge->project(chord.b).arc_length;
    const double lo = std::min(sa, sb) - 0.25, hi = std::max(sa, sb) + 0.25;
    const int pieces = std::max(1, static_cast<int>(std::ceil(line.vehicle.length() / piece_m)));
    const double sigma = sigma_m * std::sqrt(static_cast<double>(pieces));
    // Re-association candidates: the segments of that stretch.
    const Polyline2 stretch = edge->slice(lo, hi);
    std::vector<Segment2> candidates;
    for (std::size_t k = 0; k < stretch.segmentCount(); ++k) candidates.push_back(stretch.segment(k));
    for (int k = 0; k < pieces; ++k) {
      const Segment2 piece{line.vehicle.pointAt(static_cast<double>(k) / pieces),
                           line.vehicle.pointAt(static_cast<double>(k + 1) / pieces)};
      const Polyline2::Projection p = edge->project(prior.transform(piece.pointAt(0.5)));
      if (p.arc_length < lo || p.arc_length > hi) continue;
      out.push_back({*line.label, piece, edge->segment(p.segment), sigma, candidates});
    }
  });
  return out;
}

std::optional<LineCorrespondence> centerlineCorrespondence(const Map& map, const Pose2& prior,
                                                           const Segment2& centerline_vehicle, double sigma_m,
                                                           double search_radius_m) {
  constexpr double kMinKeep = 1.0;  // m of the detected line kept at least
  const Vec2 mid = prior.transform(centerline_vehicle.pointAt(0.5));
  const Road* best = nullptr;
  Polyline2::Projection best_projection;
  for (const Road* road : map.roadsNear(mid, search_radius_m)) {
    const Polyline2::Projection p = road->centerline.project(mid);
    if (p.distance <= search_radius_m && (best == nullptr || p.distance < best_projection.distance)) {
      best = road;
      best_projection = p;
    }
  }
  if (best == nullptr || best->centerline.segmentCount() == 0) return std::nullopt;
  // The detected centre line is straight; on a curve the road's centre line over the same stretch
  // is an arc. Matching it against the one map segment under its midpoint (a tangent there) put
  // its ends a sagitta off that line: on park_loop's curves the gate then rejected frame after
  // frame and the estimate drifted off the path on odometry alone. So: the map's chord between the
  // points the detected ends project to. And the straight model holds near the vehicle only (the
  // image rows, which the road finder weighs alike, are mostly near: half of them see 2 to 3.7 m
  // ahead with the Terregator camera), so the detected line is cut back from its far end until
  // that chord is within sigma_m of the arc; what deviation is left is added to sigma.
  const Polyline2& line = best->centerline;
  const bool a_near = centerline_vehicle.a.norm() <= centerline_vehicle.b.norm();
  const Vec2 near = a_near ? centerline_vehicle.a : centerline_vehicle.b;
  const Vec2 far = a_near ? centerline_vehicle.b : centerline_vehicle.a;
  const double length = (far - near).norm();
  if (length < 1e-9) {
    return LineCorrespondence{best->id + ".centerline", centerline_vehicle, line.segment(best_projection.segment),
                              sigma_m, {}};
  }
  const double sn = line.project(prior.transform(near)).arc_length;
  for (double keep = length;; keep = std::max(kMinKeep, keep - 0.25)) {
    const Vec2 end = near + (far - near) * (keep / length);
    const double se = line.project(prior.transform(end)).arc_length;
    if (std::abs(se - sn) < 0.5) {  // no stretch of road under it: the segment under its midpoint
      return LineCorrespondence{best->id + ".centerline", centerline_vehicle, line.segment(best_projection.segment),
                                sigma_m, {}};
    }
    const Segment2 chord{line.pointAt(sn), line.pointAt(se)};
    double sagitta = 0;
    const double lo = std::min(sn, se), hi = std::max(sn, se);
    const int steps = static_cast<int>(std::ceil((hi - lo) / 0.25));
    for (int k = 1; k < steps; ++k) {
      sagitta = std::max(sagitta, chord.distanceTo(line.pointAt(lo + (hi - lo) * k / steps)));
    }
    if (sagitta <= sigma_m || keep <= kMinKeep) {
      return LineCorrespondence{best->id + ".centerline", Segment2{near, end}, chord, std::hypot(sigma_m, sagitta), {}};
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The filter

PoseFilter::PoseFilter(const Pose2& pose, const Mat3& covariance, const FilterOptions& options)
    : pose_(pose), covariance_(covariance), options_(options) {
  options_.validate();
  const bool symmetric = (covariance - covariance.transpose()).cwiseAbs().maxCoeff() <= 1e-9 * (1 + covariance.norm());
  if (!covariance.allFinite() || !symmetric || covariance.llt().info() != Eigen::Success) {
    throw InvalidInput("PoseFilter: the covariance must be finite, symmetric and positive definite");
  }
}

void PoseFilter::predict(const MotionIncrement& motion) {
  const double d = motion.distance_m, dh = motion.dheading_rad;
  const double hm = pose_.heading() + 0.5 * dh;  // the mid-step heading
  const double c = std::cos(hm), s = std::sin(hm);
  Mat3 f = Mat3::Identity();  // d(new state) / d(state)
  f(0, 2) = -d * s;
  f(1, 2) = d * c;
  Eigen::Matrix<double, 3, 2> g;  // d(new state) / d(distance, heading change)
  g << c, -0.5 * d * s, s, 0.5 * d * c, 0, 1;
  const MotionNoiseOptions& m = options_.motion;
  const double var_d = std::pow(m.distance_sigma_per_m * d, 2);
  const double var_h = std::pow(m.heading_sigma_per_rad * dh, 2) + std::pow(m.heading_sigma_per_m * d, 2);
  const Mat2 q = Eigen::Vector2d(var_d, var_h).asDiagonal();
  const Mat3 base = Vec3(m.base_sigma_m * m.base_sigma_m, m.base_sigma_m * m.base_sigma_m,
                         m.base_heading_sigma_rad * m.base_heading_sigma_rad)
                        .asDiagonal();
  covariance_ = f * covariance_ * f.transpose() + g * q * g.transpose() + base;
  covariance_ = 0.5 * (covariance_ + covariance_.transpose());
  pose_ = Pose2(pose_.x() + d * c, pose_.y() + d * s, pose_.heading() + dh);
}

CurrentPosition PoseFilter::current(double timestamp, std::string reason) const {
  CurrentPosition out;
  out.timestamp = timestamp;
  out.pose = pose_;
  out.covariance = covariance_;
  out.status = PositionStatus::OdometryOnly;
  out.reason = std::move(reason);
  return out;
}

namespace {

std::string joined(const std::vector<std::string>& ids) {
  std::string out;
  for (const std::string& id : ids) out += (out.empty() ? "" : ", ") + id;
  return out;
}

std::string format(const char* pattern, double a, double b, int c) {
  char text[160];
  std::snprintf(text, sizeof text, pattern, a, b, c);
  return text;
}

}  // namespace

CurrentPosition PoseFilter::update(const std::vector<LineCorrespondence>& lines, double timestamp) {
  const LineMatchOptions& mo = options_.match;
  if (lines.empty()) return current(timestamp, "no usable lines: odometry only");

  // 1. The robust fit from the prior: which correspondences are inliers, and the pose they give.
  const std::optional<LineFit> fit = fitPoseToLines(pose_, lines, mo);
  if (!fit) return current(timestamp, "no line is an inlier: odometry only");

  // 2. The gate: the fitted pose against the prior in the observed directions U, where the fit's
  //    covariance is diag(1 / eigenvalue): d^2 = e^T (U^T P U + Lambda^-1)^-1 e, e = U^T (fit - prior).
  const Vec3 prior = toVec(pose_);
  Eigen::SelfAdjointEigenSolver<Mat3> eig(fit->information);
  std::vector<int> kept;
  for (int i = 0; i < 3; ++i) {
    if (eig.eigenvalues()(i) >= mo.min_information && eig.eigenvalues()(i) > 0) kept.push_back(i);
  }
  const int dof = static_cast<int>(kept.size());
  if (dof == 0) return current(timestamp, "the lines constrain no direction: odometry only");
  Eigen::MatrixXd u(3, dof);
  Eigen::VectorXd fit_variance(dof);
  for (int i = 0; i < dof; ++i) {
    u.col(i) = eig.eigenvectors().col(kept[static_cast<std::size_t>(i)]);
    fit_variance(i) = 1.0 / eig.eigenvalues()(kept[static_cast<std::size_t>(i)]);
  }
  const Eigen::VectorXd e = u.transpose() * difference(toVec(fit->pose), prior);
  const Eigen::MatrixXd s = u.transpose() * covariance_ * u + Eigen::MatrixXd(fit_variance.asDiagonal());
  const double d2 = e.dot(s.ldlt().solve(e));
  const boost::math::chi_squared_distribution<double> chi2(dof);
  const double limit = boost::math::quantile(chi2, options_.gate_probability);
  if (!(d2 <= limit)) {
    CurrentPosition out = current(
        timestamp,
        format("rejected: the lines disagree with the prior (Mahalanobis d^2 = %.1f > %.1f, %d dof); odometry only",
               d2, limit, dof));
    out.status = PositionStatus::Rejected;
    out.mahalanobis_d2 = d2;
    out.outliers = fit->outliers;
    return out;
  }

  // 3. Iterated EKF update with the inliers' point-to-line distances (measured 0) as the
  //    measurement: Gauss-Newton on |x - prior|^2_{P^-1} + sum r_i(x)^2 / sigma_i^2.
  //    Lines with candidates start from the fit's association and are re-associated at every iterate.
  std::vector<LineCorrespondence> inliers;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    const auto& out = fit->outlier_indices;
    if (std::find(out.begin(), out.end(), i) != out.end()) continue;
    inliers.push_back(lines[i]);
    inliers.back().map_world = fit->map_lines[i];
  }
  //    The measurement is used only in the observed directions U (J projected onto U): a direction
  //    the lines determine worse than min_information allows (a line a few degrees off the road's
  //    direction "observes" the along-road position through its slant alone, where a few
  //    centimetres of map or detection error become decimetres) gets no correction.
  Problem problem(inliers, mo.reassociate_max_angle_deg);
  const std::vector<PointObs>& pts = problem.pts;
  const std::vector<char> all(inliers.size(), 1);
  const Mat3 prior_information = covariance_.inverse();
  const Mat3 project = u * u.transpose();
  Vec3 x = prior;
  for (int it = 0; it < options_.update_iterations; ++it) {
    if (it > 0) problem.reassociate(x);  // the first iterate is the prior: keep the fit's association
    Mat3 a = Mat3::Zero();
    Vec3 g = Vec3::Zero();
    for (const PointObs& p : pts) {
      const Vec3 j = jacobian(p, x);
      a += j * j.transpose() / (p.sigma * p.sigma);
      g += j * residual(p, x) / (p.sigma * p.sigma);
    }
    const Vec3 step = (prior_information + project * a * project)
                          .ldlt()
                          .solve(-prior_information * difference(x, prior) - project * g);
    x += step;
    x.z() = normalizeAngle(x.z());
    if (step.norm() < mo.step_tolerance) break;
  }
  const Mat3 information = project * informationOf(pts, all, x) * project;
  Mat3 posterior = (prior_information + information).inverse();
  posterior = 0.5 * (posterior + posterior.transpose());

  pose_ = toPose(x);
  covariance_ = posterior;
  CurrentPosition out = current(timestamp, "");
  out.status = PositionStatus::Corrected;
  out.information = information;
  const Observability seen = observability(information, pose_.heading(), mo.min_information);
  out.observed_lateral = seen.lateral;
  out.observed_along = seen.along;
  out.observed_heading = seen.heading;
  out.lines_used = static_cast<int>(inliers.size());
  out.outliers = fit->outliers;
  out.mahalanobis_d2 = d2;
  out.reason = "corrected from " + std::to_string(inliers.size()) + " line(s)";
  if (!fit->outliers.empty()) out.reason += ", outliers rejected: " + joined(fit->outliers);
  if (!seen.along) out.reason += "; along-road position from odometry";
  if (!seen.lateral) out.reason += "; lateral position from odometry";
  return out;
}

std::optional<double> groundMetresPerPixel(const Camera& camera, const Segment2& line) {
  const Vec2 mid = line.pointAt(0.5);
  const Vec2 half = 0.05 * line.direction();  // 10 cm of the line about its midpoint, for its image direction
  const auto p = camera.projectGround(mid), a = camera.projectGround(mid - half), b = camera.projectGround(mid + half);
  if (!p || !a || !b || (*b - *a).norm() < 1e-9) return std::nullopt;
  const auto q = camera.backproject(*p + leftNormal((*b - *a).normalized()));  // one pixel across the image line
  if (!q) return std::nullopt;
  return std::abs((*q - mid).dot(leftNormal(line.direction())));
}

CurrentPosition localize(PoseFilter& filter, const MotionIncrement& motion, const Prediction& prediction,
                         const DetectedObject& detected, const LocalizeOptions& options, const Map* map,
                         const Camera* camera) {
  options.validate();
  filter.predict(motion);
  const double t = detected.timestamp;
  if (detected.status != DetectedObject::Status::Ok) {
    return filter.current(t, "vision failed (" + detected.reason + "): odometry only");
  }
  std::vector<LineCorrespondence> lines =
      map != nullptr && options.curve_piece_m > 0
          ? edgeCorrespondences(*map, prediction, detected, filter.pose(), options.edge_sigma_m,
                                options.min_line_length_m, options.curve_piece_m)
          : labelledCorrespondences(prediction, detected, options.edge_sigma_m, options.min_line_length_m);
  if (camera != nullptr && options.edge_sigma_px > 0) {
    for (LineCorrespondence& c : lines) {
      if (const auto mpp = groundMetresPerPixel(*camera, c.detected_vehicle)) {
        c.sigma_m = std::hypot(c.sigma_m, options.edge_sigma_px * *mpp);
      }
    }
  }
  bool park = false;
  if (lines.empty() && map != nullptr && detected.centerline_vehicle &&
      detected.centerline_vehicle->length() >= options.min_line_length_m) {
    if (auto c = centerlineCorrespondence(*map, filter.pose(), *detected.centerline_vehicle,
                                          options.centerline_sigma_m, options.centerline_search_m)) {
      lines.push_back(*c);
      park = true;
    }
  }
  if (lines.empty()) {
    const bool any_label = std::any_of(detected.lines.begin(), detected.lines.end(),
                                       [](const DetectedLine& l) { return l.label && !l.frame_edge; });
    return filter.current(t, any_label ? "no usable lines (no label matches a predicted segment): odometry only"
                                       : "no usable lines (none labelled, no centre line): odometry only");
  }
  CurrentPosition out = filter.update(lines, t);
  if (park) out.reason = "park mode, " + out.reason;
  return out;
}

}  // namespace mapnav
