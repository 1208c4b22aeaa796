// The pose filter: odometry prediction, the gate and the iterated EKF update (pose_filter.h).
#include "mapnav/localization/pose_filter.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <boost/math/distributions/chi_squared.hpp>

#include "line_problem.h"
#include "mapnav/core/error.h"
#include "mapnav/core/options.h"
#include "mapnav/core/strprintf.h"

namespace mapnav {

using namespace localization::detail;

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
        strprintf("rejected: the lines disagree with the prior (Mahalanobis d^2 = %.1f > %.1f, %d dof); odometry only",
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

}  // namespace mapnav
