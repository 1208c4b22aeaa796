// The robust line fit: Huber then Cauchy IRLS by damped Gauss-Newton in the observed directions,
// inlier selection, and a final least-squares solve on the inliers (line_fit.h).
#include "mapnav/localization/line_fit.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include <Eigen/Cholesky>

#include "line_problem.h"

namespace mapnav {

using namespace localization::detail;

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

const OptionTable<LineMatchOptions>& lineMatchOptionTable() {
  using O = LineMatchOptions;
  static const OptionTable<O> table =
      OptionTable<O>("LineMatchOptions")
          .choice("loss", &O::loss,
                  {{RobustLoss::None, "none"}, {RobustLoss::Huber, "huber"}, {RobustLoss::Cauchy, "cauchy"}},
                  "the robust loss on each normalised residual")
          .field("loss_scale", &O::loss_scale, above(0), "the loss's scale, sigmas of the normalised residual")
          .field("inlier_threshold", &O::inlier_threshold, above(0),
                 "after the robust solve, an end point farther than this many sigmas from its line is an outlier")
          .field("max_iterations", &O::max_iterations, atLeast(1),
                 "Gauss-Newton / Levenberg-Marquardt iterations at most, per stage")
          .field("step_tolerance", &O::step_tolerance, above(0),
                 "stop when a step is shorter than this (m and rad together)")
          .field("min_information", &O::min_information, atLeast(0),
                 "an eigen-direction of the information with less than this is unobserved, 1/m^2 or 1/rad^2")
          .field("reassociate_max_angle_deg", &O::reassociate_max_angle_deg, aboveUpTo(0, 90),
                 "re-association takes a candidate line at more than this angle only when none is closer in "
                 "angle, degrees");
  return table;
}

void LineMatchOptions::validate() const { lineMatchOptionTable().validate(*this); }

namespace {

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

}  // namespace mapnav
